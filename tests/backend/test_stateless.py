"""POST /api/solve and /api/overlay: the solver over HTTP, for scripts."""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest
from fastapi.testclient import TestClient
from phones import TEMPLE

from shared_solver import solve
from testbed.scenes import facing_scene, temple_scene


def request_for(seed: int, landmarks: int = 6) -> dict[str, object]:
    s = facing_scene(np.random.default_rng(seed), landmarks)
    return {
        "points1": s.landmarks1.tolist(),
        "points2": s.landmarks2.tolist(),
        "epipole1": s.epipole1.tolist(),
        "tap_sigma": 1.5,
        "image_size1": list(s.image_size1),
        "image_size2": list(s.image_size2),
    }


@pytest.mark.parametrize("seed", range(3))
def test_solve_returns_exactly_what_the_solver_returns(client: TestClient, seed: int) -> None:
    body = request_for(seed)
    response = client.post("/api/solve", json=body)
    assert response.status_code == 200
    expected = solve(
        body["points1"],  # type: ignore[arg-type]
        body["points2"],  # type: ignore[arg-type]
        epipole1=body["epipole1"],  # type: ignore[arg-type]
        tap_sigma=1.5,
        image_size1=body["image_size1"],  # type: ignore[arg-type]
        image_size2=body["image_size2"],  # type: ignore[arg-type]
    )
    assert response.json() == json.loads(json.dumps(expected.model_dump(mode="json")))


@pytest.mark.parametrize(
    ("change", "code"),
    [
        ({"points1": [[1, 2]] * 3, "points2": [[1, 2]] * 3}, "too_few_landmarks"),
        ({"points2": [[1, 2, 3]] * 6}, "invalid_shape"),
        ({"points1": "nowhere"}, "invalid_shape"),
        ({"epipole1": [1]}, "invalid_shape"),
        ({"tap_sigma": -1}, "invalid_parameter"),
        ({"epipole2": [5, 5], "epipole1": None}, "missing_epipole1"),
    ],
)
def test_solve_refuses_with_the_solvers_code(
    client: TestClient, change: dict[str, object], code: str
) -> None:
    response = client.post("/api/solve", json=request_for(0) | change)
    assert response.status_code == 422
    assert response.json()["error"]["code"] == code


def test_solve_refuses_nan_with_not_finite(client: TestClient) -> None:
    text = json.dumps(request_for(0)).replace(
        '"tap_sigma": 1.5', '"tap_sigma": 1.5, "epipole1": [NaN, 3]'
    )
    response = client.post("/api/solve", content=text, headers={"Content-Type": "application/json"})
    assert response.status_code == 422
    assert response.json()["error"]["code"] == "not_finite"


@pytest.mark.parametrize("body", [b"{not json", b"[]", b'{"points1": [[1, 2]]}'])
def test_solve_refuses_malformed_requests(client: TestClient, body: bytes) -> None:
    response = client.post("/api/solve", content=body, headers={"Content-Type": "application/json"})
    assert response.status_code == 422
    assert response.json()["error"]["code"] == "invalid_request"


def temple_request() -> dict[str, object]:
    s = temple_scene(
        TEMPLE / "templeSR_par.txt", "templeSR0003", "templeSR0006", 6, np.random.default_rng(4)
    )
    return {
        "points1": s.landmarks1.tolist(),
        "points2": s.landmarks2.tolist(),
        "epipole1": s.epipole1.tolist(),
        "image_size1": [640, 480],
        "image_size2": [640, 480],
    }


@pytest.mark.parametrize(("fmt", "magic"), [("png", b"\x89PNG"), ("jpeg", b"\xff\xd8\xff")])
def test_overlay_draws_on_the_buddys_photo(client: TestClient, fmt: str, magic: bytes) -> None:
    photo = (TEMPLE / "templeSR0006.png").read_bytes()
    response = client.post(
        "/api/overlay",
        params={"format": fmt},
        files={"photo": ("buddy.png", photo, "image/png")},
        data={"request": json.dumps(temple_request())},
    )
    assert response.status_code == 200, response.text
    assert response.content.startswith(magic)
    drawn = cv2.imdecode(np.frombuffer(response.content, np.uint8), cv2.IMREAD_COLOR)
    plain = cv2.imread(str(TEMPLE / "templeSR0006.png"))
    assert drawn.shape == plain.shape
    assert np.mean(np.any(drawn != plain, axis=2)) > 0.005  # something was drawn


def test_overlay_refuses_a_non_image_and_a_bad_request(client: TestClient) -> None:
    not_a_photo = client.post(
        "/api/overlay",
        files={"photo": ("x.jpg", b"%PDF-1.4 hello", "image/jpeg")},
        data={"request": json.dumps(temple_request())},
    )
    assert not_a_photo.status_code == 415
    assert not_a_photo.json()["error"]["code"] == "unsupported_media_type"
    photo = (TEMPLE / "templeSR0006.png").read_bytes()
    bad = client.post(
        "/api/overlay", files={"photo": ("b.png", photo, "image/png")}, data={"request": "{"}
    )
    assert bad.status_code == 422
    assert bad.json()["error"]["code"] == "invalid_request"
    missing = client.post("/api/overlay", data={"request": json.dumps(temple_request())})
    assert missing.status_code == 422
