"""The two-phone flow over the API: pairing, photos, taps, the answer, pictures, the end."""

from __future__ import annotations

import zlib
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import cv2
import httpx2
import numpy as np
import pytest
from fastapi.testclient import TestClient
from phones import TEMPLE, FakeClock, Phone
from sqlalchemy import text

from backend.pairing.tokens import token_hash
from backend.storage.tables import Base
from shared_solver.estimation.uncertainty import contains
from testbed.scenes import Scene, temple_scene


def error_of(response: Any) -> str:
    body = response.json()
    assert set(body) == {"error"}, body
    assert set(body["error"]) == {"code", "message"}, body
    assert body["error"]["message"]
    return str(body["error"]["code"])


def scene(landmarks: int, seed: int = 0) -> Scene:
    return temple_scene(
        TEMPLE / "templeSR_par.txt",
        "templeSR0003",
        "templeSR0006",
        landmarks,
        np.random.default_rng(seed),
    )


def landmarks(points: np.ndarray, ids: list[int] | None = None) -> list[dict[str, float]]:
    ids = ids or list(range(1, len(points) + 1))
    return [{"id": i, "x": float(x), "y": float(y)} for i, (x, y) in zip(ids, points, strict=True)]


def photos_uploaded(seeker: Phone, buddy: Phone, photos: tuple[bytes, bytes]) -> None:
    for phone, photo in zip((seeker, buddy), photos, strict=True):
        stored = phone.upload(photo, "photo.png")
        assert stored.status_code == 200, stored.text
        assert stored.json() == {"width": 640, "height": 480, "scale": 1.0}


# --- pairing --------------------------------------------------------------------------


def test_a_session_starts_with_a_code_and_a_link(client: TestClient) -> None:
    created = client.post("/api/sessions")
    assert created.status_code == 201
    body = created.json()
    assert body["role"] == "seeker"
    assert len(body["join_code"]) == 8
    assert body["join_code"].isdigit()
    assert body["join_url"].endswith(f"/join/{body['join_code']}")
    assert len(body["token"]) >= 40
    assert body["expires_at"] > body["join_code_expires_at"]


def test_the_buddy_joins_once_and_a_third_phone_is_refused(
    client: TestClient, seeker: Phone
) -> None:
    code = seeker.state()["join_code"]
    first = client.post("/api/sessions/join", json={"code": code})
    assert first.status_code == 200
    assert first.json()["role"] == "buddy"
    assert first.json()["session_id"] == seeker.session_id
    third = client.post("/api/sessions/join", json={"code": code})
    assert third.status_code == 404
    assert error_of(third) == "invalid_join_code"
    state = seeker.state()
    assert state["participants"]["buddy"]["joined"] is True
    assert state["join_code"] is None


def test_join_codes_expire(client: TestClient, seeker: Phone, clock: FakeClock) -> None:
    state = seeker.state()
    code = state["join_code"]
    assert state["join_code_expires_at"].startswith("2026-11-21T20:10:00")  # 10 minutes
    clock.advance(601)
    assert seeker.state()["join_code"] is None
    late = client.post("/api/sessions/join", json={"code": code})
    assert late.status_code == 404
    assert error_of(late) == "invalid_join_code"


FULL_WIDTH_DIGITS = "".join(chr(0xFF10 + int(d)) for d in "12345678")  # \d matches them


@pytest.mark.parametrize(
    "code", ["123456", "1234567", "123456789", "abcdefgh", "1234 5678", FULL_WIDTH_DIGITS, ""]
)
def test_malformed_join_codes_are_refused(client: TestClient, code: str) -> None:
    response = client.post("/api/sessions/join", json={"code": code})
    assert response.status_code == 422
    assert error_of(response) == "invalid_request"


# --- who may do what ------------------------------------------------------------------


def test_a_token_opens_only_its_own_session(client: TestClient, seeker: Phone) -> None:
    other = client.post("/api/sessions").json()
    response = client.get(seeker.url(), headers={"Authorization": f"Bearer {other['token']}"})
    assert response.status_code == 403
    assert error_of(response) == "forbidden"
    missing = client.get(seeker.url())
    assert missing.status_code == 401
    assert error_of(missing) == "unauthorized"
    wrong = client.get(seeker.url(), headers={"Authorization": "Bearer not-a-token"})
    assert wrong.status_code == 401


def test_tokens_are_stored_hashed(client: TestClient, seeker: Phone) -> None:
    engine = client.app.state.services.database.engine  # type: ignore[attr-defined]
    if engine.dialect.name == "sqlite":  # the file and its write-ahead log, byte for byte
        files = (Path(engine.url.database), Path(f"{engine.url.database}-wal"))
        stored = b"".join(file.read_bytes() for file in files if file.exists())
    else:  # every row of every table, as PostgreSQL writes it out
        with engine.connect() as connection:
            rows = [
                row
                for table in Base.metadata.sorted_tables
                for row in connection.scalars(text(f"SELECT t::text FROM {table.name} t"))
            ]
        stored = "\n".join(rows).encode()
    assert token_hash(seeker.token).encode() in stored
    assert seeker.token.encode() not in stored


# --- photos and taps ------------------------------------------------------------------


def test_taps_need_a_photo_first(seeker: Phone, buddy: Phone) -> None:
    response = seeker.tap(landmarks=[{"id": 1, "x": 10, "y": 10}])
    assert response.status_code == 409
    assert error_of(response) == "photo_missing"


@pytest.mark.parametrize(
    ("role", "taps", "code"),
    [
        ("seeker", {"landmarks": [{"id": 1, "x": 700, "y": 10}]}, "outside_photo"),
        ("seeker", {"landmarks": [{"id": 1, "x": 10, "y": -1}]}, "outside_photo"),
        ("seeker", {"epipole1": [641, 10]}, "outside_photo"),
        (
            "seeker",
            {"landmarks": [{"id": 2, "x": 1, "y": 1}, {"id": 2, "x": 5, "y": 5}]},
            "duplicate_landmark",
        ),
        ("seeker", {"epipole2": [10, 10]}, "not_your_mark"),
        ("buddy", {"epipole1": [10, 10]}, "not_your_mark"),
        ("buddy", {"epipolar_line1": [1, 0, -5]}, "not_your_mark"),
        ("seeker", {"epipole1": [10, 10], "epipolar_line1": [1, 0, -5]}, "conflicting_inputs"),
        ("seeker", {"epipolar_line1": [0, 0, 1]}, "invalid_line"),
        ("seeker", {"landmarks": [{"id": 0, "x": 1, "y": 1}]}, "invalid_request"),
        ("seeker", {"landmarks": [{"id": 1, "x": "left", "y": 1}]}, "invalid_request"),
        ("seeker", {"epipole1": [1, 2, 3]}, "invalid_request"),
    ],
)
def test_bad_taps_are_refused_with_a_code(
    seeker: Phone,
    buddy: Phone,
    temple_photos: tuple[bytes, bytes],
    role: str,
    taps: dict[str, Any],
    code: str,
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    phone = seeker if role == "seeker" else buddy
    response = phone.tap(**taps)
    assert response.status_code == 422, response.text
    assert error_of(response) == code


def test_non_finite_taps_are_refused(
    client: TestClient, seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    raw = b'{"landmarks": [{"id": 1, "x": NaN, "y": 3}]}'
    response = client.put(
        seeker.url("/taps"),
        headers={**seeker.auth, "Content-Type": "application/json"},
        content=raw,
    )
    assert response.status_code == 422
    assert error_of(response) == "invalid_request"


def test_too_many_landmarks_are_refused(
    seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    many = [{"id": i, "x": i % 600, "y": i % 400} for i in range(1, 66)]
    response = seeker.tap(landmarks=many)
    assert response.status_code == 422
    assert error_of(response) == "too_many_landmarks"


def test_the_answer_follows_the_taps(
    seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """Phone photos: three landmarks and the buddy give a position (the solver's camera
    model); the counter counts down to it and the answer holds the truth in its region."""
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(6, seed=2)
    seeker.tap(landmarks=landmarks(s.landmarks1[:2]), epipole1=list(s.epipole1))
    state = buddy.tap(landmarks=landmarks(s.landmarks2[:2])).json()
    assert state["result"] is None
    assert state["landmarks_needed"] == 1

    seeker.tap(landmarks=landmarks(s.landmarks1[:3]), epipole1=list(s.epipole1))
    state = buddy.tap(landmarks=landmarks(s.landmarks2[:3])).json()
    assert state["result"]["method"] == "pinhole_epipole"
    assert state["result"]["camera_model"] == "pinhole"
    assert [camera["known"] for camera in state["result"]["cameras"]] == ["phone", "phone"]
    assert state["landmarks_needed"] == 0

    # Ids match across photos whatever the order they were tapped in.
    seeker.tap(landmarks=landmarks(s.landmarks1[:5]), epipole1=list(s.epipole1))
    state = buddy.tap(landmarks=landmarks(s.landmarks2[4::-1], [5, 4, 3, 2, 1])).json()
    result = state["result"]
    assert result["method"] == "pinhole_epipole"
    assert state["landmarks_needed"] == 0
    assert state["result_landmark_ids"] == [1, 2, 3, 4, 5]
    assert contains(
        np.array(result["epipole2"]), np.array(result["uncertainty"]["covariance"]), s.epipole2
    )
    assert state["result_version"] == state["version"]
    assert seeker.state()["result"] == result  # both phones see the same answer


@pytest.mark.parametrize(
    ("marks", "fewest"),
    [
        ({}, 7),  # nothing marked
        ({"epipolar_line1": "line"}, 6),  # a line through the buddy
        ({"epipole1": "buddy"}, 3),  # the buddy (5 without the phone cameras)
    ],
)
def test_the_counter_counts_down_to_what_the_solver_needs_from_phones(
    seeker: Phone,
    buddy: Phone,
    temple_photos: tuple[bytes, bytes],
    marks: dict[str, str],
    fewest: int,
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(7, seed=5)
    drawn = {
        "epipole1": list(s.epipole1),
        "epipolar_line1": [1.0, 0.0, -float(s.epipole1[0])],  # vertical, through the buddy
    }
    mark = {name: drawn[name] for name in marks}
    seeker.tap(landmarks=landmarks(s.landmarks1), **mark)
    for n in range(fewest):
        state = buddy.tap(landmarks=landmarks(s.landmarks2[:n])).json()
        assert state["landmarks_needed"] == fewest - n
        assert state["result"] is None
    state = buddy.tap(landmarks=landmarks(s.landmarks2[:fewest])).json()
    assert state["landmarks_needed"] == 0
    assert state["result"]["camera_model"] == "pinhole"


def test_both_friends_marked_one_landmark_is_enough(
    seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """Each sees the other: with phone photos one common landmark fixes the seeker (three
    for any two cameras)."""
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(3, seed=13)
    seeker.tap(landmarks=landmarks(s.landmarks1), epipole1=list(s.epipole1))
    state = buddy.tap(landmarks=[], epipole2=list(s.epipole2)).json()
    assert state["landmarks_needed"] == 1
    assert state["result"] is None
    state = buddy.tap(landmarks=landmarks(s.landmarks2[:1]), epipole2=list(s.epipole2)).json()
    assert state["landmarks_needed"] == 0
    result = state["result"]
    assert result["method"] == "pinhole_two_epipoles"
    assert result["camera_model"] == "pinhole"
    assert np.linalg.norm(np.array(result["epipole2"]) - s.epipole2) < 3.0


# Taps that fit no two phone photos (found by search: no pose of two phone cameras puts
# these landmarks and the buddy where they were tapped); any two cameras can still answer.
NO_PHONES_1 = np.array([[350, 196], [408, 130], [302, 41], [424, 386], [200, 300]], float)
NO_PHONES_2 = np.array([[521, 390], [150, 433], [349, 114], [91, 68], [300, 250]], float)
NO_PHONES_BUDDY = [397.0, 291.0]


def test_taps_that_fit_no_phones_are_answered_without_the_camera_model(
    seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """The solver falls back to the projective geometry, and says so: four landmarks give
    the curve the seeker is on, and the counter asks for the fifth that fixes the spot."""
    photos_uploaded(seeker, buddy, temple_photos)
    seeker.tap(landmarks=landmarks(NO_PHONES_1), epipole1=NO_PHONES_BUDDY)
    state = buddy.tap(landmarks=landmarks(NO_PHONES_2[:3])).json()
    assert state["result"] is None
    assert state["result_error"]["code"] == "degenerate_configuration"

    state = buddy.tap(landmarks=landmarks(NO_PHONES_2[:4])).json()
    result = state["result"]
    assert result["method"] == "conic"
    assert result["camera_model"] == "projective"
    assert "do not fit two ordinary phone photos" in result["warnings"][0]
    assert state["landmarks_needed"] == 1  # the curve: one more for a position
    assert seeker.state()["landmarks_needed"] == 1

    state = buddy.tap(landmarks=landmarks(NO_PHONES_2)).json()
    assert state["result"]["method"] == "five_point_epipole"
    assert state["result"]["camera_model"] == "projective"
    assert state["landmarks_needed"] == 0


def test_the_reply_to_taps_is_the_state_a_fetch_then_shows(
    seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """The taps and their answer are one write: the reply is what the other phone sees."""
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(6, seed=3)
    seeker.tap(landmarks=landmarks(s.landmarks1), epipole1=list(s.epipole1))
    for n in (2, 3, 6):  # no answer yet, then answers
        reply = buddy.tap(landmarks=landmarks(s.landmarks2[:n])).json()
        assert reply == buddy.state()
        fetched = seeker.state()
        for key in ("version", "result", "result_version", "result_error", "taps"):
            assert fetched[key] == reply[key]
    assert reply["result"]["method"] == "pinhole_epipole"  # 6 landmarks + e1, phone cameras


def overtake_the_buddy(
    app: Any, seeker: Phone, s: Scene, then: Callable[[], httpx2.Response] | None = None
) -> list[httpx2.Response]:
    """Make the buddy's next taps overtaken: the seeker's taps of all ``s``'s landmarks land
    between the buddy's request reading the session and writing its own. Filled in as it
    happens: the seeker's reply, then (if given) what ``then`` got right after the buddy's
    write, before its request answered the session again."""
    store = app.state.services.taps.taps
    write = store.put_taps
    got: list[httpx2.Response] = []

    def overtaken(participant: Any, *args: Any) -> Any:
        if got or participant.role != "buddy":
            return write(participant, *args)
        got.append(seeker.tap(landmarks=landmarks(s.landmarks1), epipole1=list(s.epipole1)))
        written = write(participant, *args)
        if then is not None:
            got.append(then())
        return written

    store.put_taps = overtaken
    return got


def test_taps_overtaken_by_the_other_phone_are_answered_afresh(
    app: Any, seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """The other phone's taps land between reading the session and writing these: the
    answer computed before that would be stale, so the new version is answered again."""
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(6, seed=4)
    seeker.tap(landmarks=landmarks(s.landmarks1[:5]), epipole1=list(s.epipole1))
    buddy.tap(landmarks=landmarks(s.landmarks2[:4]))
    sneaked = overtake_the_buddy(app, seeker, s)
    reply = buddy.tap(landmarks=landmarks(s.landmarks2)).json()
    assert sneaked[0].status_code == 200
    # Answered with the seeker's 6 landmarks, which came in after the buddy's request did.
    assert reply["result"]["method"] == "pinhole_epipole"
    assert reply["result_landmark_ids"] == [1, 2, 3, 4, 5, 6]
    assert reply["result_version"] == reply["version"] == sneaked[0].json()["version"] + 1
    assert reply == buddy.state()


def test_landmarks_tapped_in_one_photo_only_do_not_count(
    seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(7)
    seeker.tap(landmarks=landmarks(s.landmarks1, [1, 2, 3, 4, 5, 6, 7]), epipole1=list(s.epipole1))
    state = buddy.tap(landmarks=landmarks(s.landmarks2[[0, 1, 2, 6]], [1, 2, 3, 9])).json()
    assert state["result"]["method"] == "pinhole_epipole"
    assert state["result_landmark_ids"] == [1, 2, 3]


def test_a_degenerate_tap_set_explains_itself(
    seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(5)
    seeker.tap(landmarks=landmarks(s.landmarks1), epipole1=list(s.landmarks1[2]))
    state = buddy.tap(landmarks=landmarks(s.landmarks2)).json()
    assert state["result"] is None
    assert state["result_error"]["code"] == "epipole_on_landmark"
    assert "#3" in state["result_error"]["message"]


def test_a_new_photo_clears_its_taps_and_the_answer(
    seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(5)
    seeker.tap(landmarks=landmarks(s.landmarks1), epipole1=list(s.epipole1))
    assert buddy.tap(landmarks=landmarks(s.landmarks2)).json()["result"] is not None
    assert buddy.upload(temple_photos[1], "again.png").status_code == 200
    state = seeker.state()
    assert state["taps"]["buddy"] is None
    assert state["taps"]["seeker"] is not None
    assert state["result"] is None


# --- pictures -------------------------------------------------------------------------


def test_overlays_show_the_answer_on_each_photo(
    client: TestClient, seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    before = client.get(seeker.url("/overlay/buddy"), headers=seeker.auth)
    assert before.status_code == 409
    assert error_of(before) == "no_result"
    s = scene(6)
    seeker.tap(landmarks=landmarks(s.landmarks1), epipole1=list(s.epipole1))
    buddy.tap(landmarks=landmarks(s.landmarks2))
    for role, fmt, magic in (("buddy", "png", b"\x89PNG"), ("seeker", "jpeg", b"\xff\xd8\xff")):
        response = client.get(
            buddy.url(f"/overlay/{role}"), params={"format": fmt}, headers=buddy.auth
        )
        assert response.status_code == 200
        assert response.content.startswith(magic)
        assert response.headers["content-type"] == f"image/{fmt}"
        image = cv2.imdecode(np.frombuffer(response.content, np.uint8), cv2.IMREAD_COLOR)
        assert image.shape == (480, 640, 3)
    again = client.get(buddy.url("/overlay/buddy"), headers=buddy.auth)
    assert again.headers["content-type"] == "image/jpeg"  # the default for a phone
    assert again.content == client.get(buddy.url("/overlay/buddy"), headers=buddy.auth).content
    # <img> cannot send headers: the token may come in the query.
    by_query = client.get(buddy.url("/overlay/buddy"), params={"token": buddy.token})
    assert by_query.status_code == 200


def test_an_overlay_asked_for_while_the_answer_is_renewed_is_drawn(
    app: Any, client: TestClient, seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """The buddy's taps are overtaken by the seeker's: they are written without their
    (stale) answer, and the answer for the session as it now is comes a moment later. An
    overlay asked for in that moment is answered then and there, not refused."""
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(6, seed=4)
    seeker.tap(landmarks=landmarks(s.landmarks1[:5]), epipole1=list(s.epipole1))
    buddy.tap(landmarks=landmarks(s.landmarks2[:5]))
    got = overtake_the_buddy(
        app, seeker, s, then=lambda: client.get(seeker.url("/overlay/buddy"), headers=seeker.auth)
    )
    reply = buddy.tap(landmarks=landmarks(s.landmarks2)).json()
    overlay = got[1]
    assert overlay.status_code == 200, overlay.text
    image = cv2.imdecode(np.frombuffer(overlay.content, np.uint8), cv2.IMREAD_COLOR)
    assert image.shape == (480, 640, 3)
    assert reply["result_landmark_ids"] == [1, 2, 3, 4, 5, 6]
    assert reply == buddy.state()


def test_the_other_phone_gets_a_crop_of_each_landmark(
    client: TestClient, seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    s = scene(3)
    seeker.tap(landmarks=landmarks(s.landmarks1))
    crop = client.get(buddy.url("/landmarks/seeker/2/crop"), headers=buddy.auth)
    assert crop.status_code == 200
    assert crop.headers["content-type"] == "image/jpeg"
    image = cv2.imdecode(np.frombuffer(crop.content, np.uint8), cv2.IMREAD_COLOR)
    assert image.shape[0] == image.shape[1] > 50
    missing = client.get(buddy.url("/landmarks/seeker/9/crop"), headers=buddy.auth)
    assert missing.status_code == 404
    assert error_of(missing) == "landmark_not_found"


# --- the end --------------------------------------------------------------------------


def test_delete_now_removes_everything_for_both_phones(
    client: TestClient, seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    deleted = client.delete(buddy.url(), headers=buddy.auth)
    assert deleted.status_code == 204
    for phone in (seeker, buddy):
        gone = client.get(phone.url(), headers=phone.auth)
        assert gone.status_code == 401
    engine = client.app.state.services.database.engine  # type: ignore[attr-defined]
    with engine.connect() as connection:
        for table in ("sessions", "participants", "photos", "events"):
            assert connection.exec_driver_sql(f"SELECT COUNT(*) FROM {table}").scalar() == 0


def test_expired_sessions_are_swept_away(
    client: TestClient,
    seeker: Phone,
    buddy: Phone,
    temple_photos: tuple[bytes, bytes],
    clock: FakeClock,
) -> None:
    photos_uploaded(seeker, buddy, temple_photos)
    services = client.app.state.services  # type: ignore[attr-defined]
    assert services.pairing.sweep() == []
    clock.advance(7201)
    assert client.get(seeker.url(), headers=seeker.auth).status_code == 401
    assert services.pairing.sweep() == [seeker.session_id]
    engine = services.database.engine
    with engine.connect() as connection:
        assert connection.exec_driver_sql("SELECT COUNT(*) FROM photos").scalar() == 0


def test_the_state_says_who_is_there(seeker: Phone, buddy: Phone) -> None:
    state = buddy.state()
    assert state["you"] == "buddy"
    assert state["join_code"] is None  # only the seeker is shown the code
    assert state["participants"]["seeker"] == {"joined": True, "online": False}
    assert state["photos"] == {"seeker": None, "buddy": None}
    version = state["version"]
    assert seeker.state()["version"] == version


def test_photo_refusals_reach_the_phone_in_the_one_shape(seeker: Phone) -> None:
    """The photo module's checks, through the route: type from the bytes, size from the
    header (a small file claiming 60 megapixels), emptiness."""
    not_a_photo = seeker.upload(b"GIF89a" + b"\0" * 100, "photo.jpg")
    assert not_a_photo.status_code == 415
    assert error_of(not_a_photo) == "unsupported_media_type"
    png = bytearray((TEMPLE / "templeSR0003.png").read_bytes())
    png[16:24] = (10000).to_bytes(4, "big") + (6000).to_bytes(4, "big")  # IHDR width, height
    png[29:33] = zlib.crc32(bytes(png[12:29])).to_bytes(4, "big")  # the chunk's CRC
    bomb = seeker.upload(bytes(png), "small.png")
    assert bomb.status_code == 413
    assert error_of(bomb) == "photo_too_large"
    empty = seeker.upload(b"", "empty.jpg")
    assert empty.status_code == 422
    assert seeker.state()["photos"]["seeker"] is None  # nothing half-stored


def test_each_phone_can_fetch_the_stored_photos(
    client: TestClient, seeker: Phone, buddy: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """The app shows the stored photo to tap on: exactly the pixels taps refer to."""
    missing = client.get(seeker.url("/photo/buddy"), headers=seeker.auth)
    assert missing.status_code == 404
    assert error_of(missing) == "photo_not_found"
    photos_uploaded(seeker, buddy, temple_photos)
    for role in ("seeker", "buddy"):
        stored = client.get(seeker.url(f"/photo/{role}"), params={"token": seeker.token})
        assert stored.status_code == 200
        assert stored.headers["content-type"] == "image/jpeg"
        image = cv2.imdecode(np.frombuffer(stored.content, np.uint8), cv2.IMREAD_COLOR)
        assert image.shape == (480, 640, 3)


def test_the_same_photo_sent_twice_at_once_is_stored_once(
    seeker: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """A phone on a bad network retries an upload that is still in flight."""
    with ThreadPoolExecutor(4) as pool:
        answers = list(pool.map(lambda _: seeker.upload(temple_photos[0], "p.png"), range(4)))
    assert [a.status_code for a in answers] == [200] * 4
    assert seeker.state()["photos"]["seeker"] == {"width": 640, "height": 480, "scale": 1.0}
