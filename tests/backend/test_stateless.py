"""POST /api/solve and /api/overlay: the solver over HTTP, for scripts."""

from __future__ import annotations

import json
from typing import Any

import cv2
import httpx2
import numpy as np
import pytest
from fastapi.testclient import TestClient
from phones import TEMPLE, error_of, image_of, scene

from shared_solver import Camera, SolveResult, solve
from testbed.phones import phone_scene
from testbed.scenes import Scene, facing_scene, solved

# No request here reaches storage: on PostgreSQL these ran the same code again.
pytestmark = pytest.mark.databases("sqlite")


def request_of(s: Scene, **more: object) -> dict[str, Any]:
    """``POST /api/solve``'s body for the scene's exact taps: landmarks, friend 1, photo sizes."""
    return {
        "points1": s.landmarks1.tolist(),
        "points2": s.landmarks2.tolist(),
        "epipole1": s.epipole1.tolist(),
        "image_size1": list(s.image_size1),
        "image_size2": list(s.image_size2),
        **more,
    }


def request_for(seed: int, landmarks: int = 6) -> dict[str, Any]:
    return request_of(facing_scene(np.random.default_rng(seed), landmarks), tap_sigma=1.5)


def answered(client: TestClient, body: dict[str, Any]) -> Any:
    """``POST /api/solve``'s answer to ``body``, failing unless 200."""
    response = client.post("/api/solve", json=body)
    assert response.status_code == 200, response.text
    return response.json()


def as_sent(result: SolveResult) -> Any:
    """The solver's ``result`` as the API sends it (JSON, read back)."""
    return json.loads(json.dumps(result.model_dump(mode="json")))


def refused_for_too_few_landmarks(client: TestClient, body: dict[str, object]) -> None:
    refused = client.post("/api/solve", json=body)
    assert error_of(refused, 422) == "too_few_landmarks"


@pytest.mark.parametrize("seed", range(3))
def test_solve_returns_exactly_what_the_solver_returns(client: TestClient, seed: int) -> None:
    body = request_for(seed)
    # The request's fields are solve's arguments.
    assert answered(client, body) == as_sent(solve(**body))


def test_solve_with_phone_cameras_needs_three_landmarks(client: TestClient) -> None:
    """Unknown cameras by default (a script may send any image); told they are phones, the
    solver answers from three landmarks with its camera model and says so."""
    s = phone_scene(np.random.default_rng(5), 3)
    body = request_of(s)
    refused_for_too_few_landmarks(client, body)
    phones = body | {
        "camera1": {"kind": "phone"},
        "camera2": {"kind": "known_focal", "focal_35mm": s.focal_35mm2},
        "points1_sigma": [1.0, 2.0, 1.0],
        "epipole1_sigma": [[2.0, 0.5], [0.5, 1.0]],
    }
    result = answered(client, phones)
    assert result["method"] == "pinhole_epipole"
    assert result["camera_model"] == "pinhole"
    assert [c["known"] for c in result["cameras"]] == ["phone", "known_focal"]
    assert result["cameras"][1]["focal_35mm"] == pytest.approx(s.focal_35mm2, rel=0.05)
    expected = solved(
        s,
        camera1="phone",
        camera2=Camera.with_focal(s.focal_35mm2),
        points1_sigma=[1.0, 2.0, 1.0],
        epipole1_sigma=[[2.0, 0.5], [0.5, 1.0]],
    )
    assert result == as_sent(expected)


def test_solve_with_both_friends_marked_needs_one_landmark_from_phones(
    client: TestClient,
) -> None:
    s = phone_scene(np.random.default_rng(7), 1)
    body = request_of(s, epipole2=s.epipole2.tolist(), tap_sigma=1.0)
    refused_for_too_few_landmarks(client, body)
    result = answered(client, body | {"camera1": "phone", "camera2": "phone"})
    assert result["method"] == "pinhole_two_epipoles"
    assert result["camera_model"] == "pinhole"
    assert [c["known"] for c in result["cameras"]] == ["phone", "phone"]
    assert result["landmark_count"] == 1


def test_solve_with_both_phones_gravity_needs_no_landmark(client: TestClient) -> None:
    """The friend mark and both phones' gravity: the level from no landmark, a point from
    one; the answers are the solver's own."""
    s = phone_scene(np.random.default_rng(8), 1, centre_sd=0.0)
    gravity = {"gravity1": s.camera1.down.tolist(), "gravity2": s.camera2.down.tolist()}
    readings = gravity | {"camera1": "phone", "camera2": "phone", "tap_sigma": 1.0}
    level = request_of(s, **readings) | {"points1": [], "points2": []}
    refused_for_too_few_landmarks(client, level | {"gravity2": None})
    result = answered(client, level)
    assert result["method"] == "pinhole_level"
    assert result["used_gravity"] is True
    assert result["epipole2"] is None
    assert result["curve2"]
    assert result["curve2_halfwidth"] > 0
    assert result == as_sent(solve(**level))
    point = answered(client, request_of(s, **readings))
    assert point["method"] == "pinhole_epipole"
    assert point["used_gravity"] is True
    assert point["epipole2"] is not None
    bad = client.post("/api/solve", json=level | {"gravity1": [0, 0, 0]})
    assert error_of(bad, 422) == "invalid_shape"
    assert "gravity1" in bad.json()["error"]["message"]
    # Both compass headings point to a stretch of the level.
    headings = {"heading1": s.camera1.heading, "heading2": s.camera2.heading}
    hinted = answered(client, level | headings | {"heading_sigma_deg": 5})
    assert hinted["used_heading"] is True
    assert hinted["curve2_stretch"]
    bent = client.post("/api/solve", json=level | headings | {"heading1": "north"})
    assert error_of(bent, 422) == "invalid_shape"
    assert "heading1" in bent.json()["error"]["message"]


def test_unknown_cameras_are_the_projective_model(client: TestClient) -> None:
    """Null cameras (the default) and "unknown" are what scripts got before cameras."""
    body = request_for(1)
    plain = answered(client, body)
    assert plain["camera_model"] == "projective"
    assert plain["cameras"] == []
    for unknown in (None, "unknown", {"kind": "unknown"}):
        said = answered(client, body | {"camera1": unknown, "camera2": unknown})
        assert said["camera_model"] == "projective"
        assert said["epipole2"] == plain["epipole2"]


def test_each_taps_own_precision_weighs_in(client: TestClient) -> None:
    """Per-tap sigmas and covariances reach the solver: the answer is the solver's for
    them, and differs from the answer with every tap at tap_sigma."""
    body = request_for(2, landmarks=8)
    sharp = [0.5, 4.0, 0.5, 4.0, 0.5, 4.0, 0.5, 4.0]
    precise = body | {
        "points1_sigma": sharp,
        "points2_sigma": [[[s**2, 0.0], [0.0, 1.0]] for s in sharp],
        "epipole1_sigma": 0.5,
    }
    weighed = answered(client, precise)
    assert weighed == as_sent(solve(**precise))
    plain = answered(client, body)
    assert weighed["uncertainty"]["covariance"] != plain["uncertainty"]["covariance"]


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"camera1": {"kind": "tripod"}}, "camera1"),
        ({"camera1": "tripod"}, "camera1"),
        ({"camera1": 26}, "camera1"),
        ({"camera1": [{"kind": "phone"}]}, "camera1"),
        ({"camera2": {"kind": "known_focal"}}, "camera2"),  # no focal length
        ({"camera2": {"kind": "phone", "focal_35mm": 26}}, "camera2"),  # focal without kind
        ({"camera2": {"kind": "known_focal", "focal_35mm": -26}}, "camera2"),
        ({"camera1": {"kind": "phone", "lens": 2}}, "camera1"),
        ({"camera1": {"kind": "phone"}, "image_size1": None}, "image_size1"),
    ],
)
def test_a_malformed_camera_is_refused_with_the_solvers_code(
    client: TestClient, change: dict[str, object], field: str
) -> None:
    response = client.post("/api/solve", json=request_for(0) | change)
    assert response.status_code == 422
    error = response.json()["error"]
    assert error["code"] == "invalid_parameter"
    assert field in error["message"]


def test_cameras_and_precisions_are_documented(client: TestClient) -> None:
    """Each new field has a description and a schema (the cameras: the solver's Camera),
    and the documented camera-aware answer is the real solver's."""
    spec = client.get("/openapi.json").json()
    schemas = spec["components"]["schemas"]
    fields = schemas["SolveRequest"]["properties"]
    for name in (
        "camera1",
        "camera2",
        "points1_sigma",
        "points2_sigma",
        "epipole1_sigma",
        "epipole2_sigma",
    ):
        assert len(fields[name]["description"]) > 20, name
        assert fields[name]["anyOf"], name
    assert {"$ref": "#/components/schemas/Camera"} in fields["camera1"]["anyOf"]
    kinds = schemas["Camera"]["properties"]["kind"]["enum"]
    assert set(kinds) == {"unknown", "phone", "known_focal"}
    requests = schemas["SolveRequest"]["examples"]
    phones = next(r for r in requests if "camera1" in r)
    answered_by = spec["paths"]["/api/solve"]["post"]["responses"]["200"]
    answers = answered_by["content"]["application/json"]["examples"]
    documented = answers["phones"]["value"]
    assert documented["camera_model"] == "pinhole"
    assert documented["landmark_count"] == 3
    # The schema leaves out nulls (FastAPI writes it without them).
    assert without_nulls(answered(client, phones)) == documented
    projective = answered(client, requests[0])
    assert without_nulls(projective) == answers["projective"]["value"]


def without_nulls(value: object) -> object:
    if isinstance(value, dict):
        return {k: without_nulls(v) for k, v in value.items() if v is not None}
    if isinstance(value, list):
        return [without_nulls(v) for v in value]
    return value


@pytest.mark.parametrize(
    ("change", "code"),
    [
        ({"points1": [[1, 2]] * 3, "points2": [[1, 2]] * 3}, "too_few_landmarks"),
        ({"points2": [[1, 2, 3]] * 6}, "invalid_shape"),
        ({"points1": "nowhere"}, "invalid_shape"),
        ({"epipole1": [1]}, "invalid_shape"),
        ({"epipole1": [float("nan"), 3]}, "not_finite"),
        ({"tap_sigma": -1}, "invalid_parameter"),
        ({"epipole2": [5, 5], "epipole1": None}, "missing_epipole1"),
        ({"points1_sigma": [1.0, 2.0]}, "invalid_shape"),  # 2 sigmas for 6 landmarks
        ({"points2_sigma": [1.0, -2.0, 1.0, 1.0, 1.0, 1.0]}, "invalid_parameter"),
        ({"points2_sigma": [[[1.0, 2.0], [2.0, 1.0]]] * 6}, "invalid_parameter"),  # indefinite
        ({"points1_sigma": "sharp"}, "invalid_shape"),
        ({"epipole1_sigma": [[1.0, 2.0], [2.0, 1.0]]}, "invalid_parameter"),
        ({"epipole1_sigma": 0}, "invalid_parameter"),
        ({"epipole1_sigma": "wide"}, "invalid_shape"),
        ({"epipole1_sigma": [1.0, 1.0]}, "invalid_shape"),
        ({"epipole2": [5, 5], "epipole2_sigma": [[1.0, 0.0], [1.0, 1.0]]}, "invalid_parameter"),
        ({"epipole1_sigma": [[1.0, float("nan")], [0.0, 1.0]]}, "not_finite"),
    ],
)
def test_solve_refuses_with_the_solvers_code(
    client: TestClient, change: dict[str, object], code: str
) -> None:
    text = json.dumps(request_for(0) | change)  # NaN is sent as JSON's NaN
    response = client.post("/api/solve", content=text, headers={"Content-Type": "application/json"})
    assert error_of(response, 422) == code


@pytest.mark.parametrize("body", [b"{not json", b"[]", b'{"points1": [[1, 2]]}'])
def test_solve_refuses_malformed_requests(client: TestClient, body: bytes) -> None:
    response = client.post("/api/solve", content=body, headers={"Content-Type": "application/json"})
    assert error_of(response, 422) == "invalid_request"


PHOTO2 = TEMPLE / "templeSR0006.png"


def temple_request() -> dict[str, Any]:
    s = scene(6, seed=4)
    return request_of(s, image_size1=[640, 480], image_size2=[640, 480])


def overlay(
    client: TestClient, request: object, photo: tuple[str, bytes, str] | None = None, **params: str
) -> httpx2.Response:
    """``POST /api/overlay`` of ``request`` (JSON unless a string) on ``photo`` (photo 2 of the
    temple pair by default)."""
    photo = photo or ("photo2.png", PHOTO2.read_bytes(), "image/png")
    text = request if isinstance(request, str) else json.dumps(request)
    return client.post(
        "/api/overlay", params=params, files={"photo": photo}, data={"request": text}
    )


def drawn_on_photo2(response: httpx2.Response) -> None:
    """A 200 answer: an image of photo 2's size, with something drawn on it."""
    drawn = image_of(response)
    plain = cv2.imread(str(PHOTO2))
    assert plain is not None
    assert drawn.shape == plain.shape
    assert np.mean(np.any(drawn != plain, axis=2)) > 0.005


@pytest.mark.parametrize(("fmt", "magic"), [("png", b"\x89PNG"), ("jpeg", b"\xff\xd8\xff")])
def test_overlay_draws_on_photo_2(client: TestClient, fmt: str, magic: bytes) -> None:
    response = overlay(client, temple_request(), format=fmt)
    drawn_on_photo2(response)
    assert response.content.startswith(magic)


def test_overlay_refuses_a_non_image_and_a_bad_request(client: TestClient) -> None:
    not_a_photo = overlay(client, temple_request(), ("x.jpg", b"%PDF-1.4 hello", "image/jpeg"))
    assert error_of(not_a_photo, 415) == "unsupported_media_type"
    bad = overlay(client, "{", ("b.png", PHOTO2.read_bytes(), "image/png"))
    assert error_of(bad, 422) == "invalid_request"
    missing = client.post("/api/overlay", data={"request": json.dumps(temple_request())})
    assert missing.status_code == 422


def test_overlay_takes_the_cameras_and_precisions_of_solve(client: TestClient) -> None:
    """The temple photos as two phone photos: three landmarks and friend 2 marked are enough for
    a drawing; a malformed camera is refused with the solver's code, as by /api/solve."""
    temple = temple_request()
    three = temple | {"points1": temple["points1"][:3], "points2": temple["points2"][:3]}
    assert overlay(client, three).json()["error"]["code"] == "too_few_landmarks"
    phones = three | {"camera1": {"kind": "phone"}, "camera2": "phone", "points1_sigma": [2, 3, 2]}
    drawn_on_photo2(overlay(client, phones))
    bad = overlay(client, phones | {"camera2": {"kind": "known_focal"}})
    assert error_of(bad, 422) == "invalid_parameter"
