"""The two-phone flow over the API: pairing, photos, taps, the answer, pictures, the end."""

from __future__ import annotations

import io
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import cv2
import httpx2
import numpy as np
import pytest
from fastapi.testclient import TestClient
from images import encoded, exif_of
from phones import (
    FakeClock,
    Phones,
    error_of,
    image_of,
    in_region,
    landmarks,
    photos_uploaded,
    scene,
    stored_photo,
    tapped_scene,
)
from PIL import ExifTags, Image
from sqlalchemy import text

from backend.pairing.tokens import token_hash
from backend.participants import ROLES
from backend.storage.snapshot import read_snapshot
from backend.storage.tables import Base
from backend.taps.schemas import StoredAnswer
from backend.wiring import Services
from shared_solver import SolveResult
from shared_solver.drawing.layout import answer_drawing
from shared_solver.drawing.overlay import render
from shared_solver.drawing.shapes import AnswerDrawing
from shared_solver.estimation.camera import focal_35mm
from testbed.client import Phone
from testbed.curves import distance_to
from testbed.scenes import (
    NO_PHONES_FRIEND,
    NO_PHONES_LANDMARKS1,
    NO_PHONES_LANDMARKS2,
    Camera,
)

# --- pairing --------------------------------------------------------------------------


def test_a_session_starts_with_a_code_and_a_link(client: TestClient) -> None:
    created = client.post("/api/sessions")
    assert created.status_code == 201
    body = created.json()
    assert body["role"] == "starter"
    assert len(body["join_code"]) == 8
    assert body["join_code"].isdigit()
    assert body["join_url"].endswith(f"/join/{body['join_code']}")
    assert len(body["token"]) >= 40
    assert body["expires_at"] > body["join_code_expires_at"]


def test_the_friend_joins_once_and_a_third_phone_is_refused(
    client: TestClient, starter: Phone
) -> None:
    code = starter.state()["join_code"]
    first = client.post("/api/sessions/join", json={"code": code})
    assert first.status_code == 200
    assert first.json()["role"] == "joiner"
    assert first.json()["session_id"] == starter.session_id
    third = client.post("/api/sessions/join", json={"code": code})
    assert error_of(third, 404) == "invalid_join_code"
    state = starter.state()
    assert state["participants"]["joiner"]["joined"] is True
    assert state["join_code"] is None


def test_join_codes_expire(client: TestClient, starter: Phone, clock: FakeClock) -> None:
    state = starter.state()
    code = state["join_code"]
    assert state["join_code_expires_at"].startswith("2026-11-21T20:10:00")  # 10 minutes
    clock.advance(601)
    assert starter.state()["join_code"] is None
    late = client.post("/api/sessions/join", json={"code": code})
    assert error_of(late, 404) == "invalid_join_code"


FULL_WIDTH_DIGITS = "".join(chr(0xFF10 + int(d)) for d in "12345678")  # \d matches them


@pytest.mark.parametrize(
    "code", ["123456", "1234567", "123456789", "abcdefgh", "1234 5678", FULL_WIDTH_DIGITS, ""]
)
def test_malformed_join_codes_are_refused(client: TestClient, code: str) -> None:
    response = client.post("/api/sessions/join", json={"code": code})
    assert error_of(response, 422) == "invalid_request"


# --- who may do what ------------------------------------------------------------------


def test_tokens_are_stored_hashed(services: Services, starter: Phone) -> None:
    engine = services.database.engine
    if engine.dialect.name == "sqlite":  # the file and its write-ahead log, byte for byte
        database = engine.url.database
        assert database is not None
        files = (Path(database), Path(f"{database}-wal"))
        stored = b"".join(file.read_bytes() for file in files if file.exists())
    else:  # every row of every table, as PostgreSQL writes it out
        with engine.connect() as connection:
            rows = [
                row
                for table in Base.metadata.sorted_tables
                for row in connection.scalars(text(f"SELECT t::text FROM {table.name} t"))
            ]
        stored = "\n".join(rows).encode()
    assert token_hash(starter.token).encode() in stored
    assert starter.token.encode() not in stored


# --- photos and taps ------------------------------------------------------------------


def test_the_answer_follows_the_taps(uploaded: Phones) -> None:
    """Phone photos: three landmarks and the joiner give a position (the solver's camera
    model); the counter counts down to it and the answer holds the truth in its region."""
    starter, joiner = uploaded
    s = scene(6, seed=2)
    starter.tap(landmarks=landmarks(s.landmarks1[:2]), friend=list(s.epipole1))
    state = joiner.tap(landmarks=landmarks(s.landmarks2[:2])).json()
    assert state["answer"] is None
    assert state["landmarks_needed"] == 1

    starter.tap(landmarks=landmarks(s.landmarks1[:3]), friend=list(s.epipole1))
    state = joiner.tap(landmarks=landmarks(s.landmarks2[:3])).json()
    assert state["answer"]["method"] == "pinhole_epipole"
    assert state["answer"]["camera_model"] == "pinhole"
    # No lens told: each photo's focal length estimated from the phone prior.
    assert all(state["answer"]["in_photo"][role]["focal_35mm"] > 0 for role in ROLES)
    assert state["photos"]["starter"]["lens"] is None
    assert state["landmarks_needed"] == 0

    # Ids match across photos whatever the order they were tapped in.
    starter.tap(landmarks=landmarks(s.landmarks1[:5]), friend=list(s.epipole1))
    state = joiner.tap(landmarks=landmarks(s.landmarks2[4::-1], [5, 4, 3, 2, 1])).json()
    answer = state["answer"]
    assert answer["method"] == "pinhole_epipole"
    assert state["landmarks_needed"] == 0
    assert answer["landmark_ids"] == [1, 2, 3, 4, 5]
    # The joiner is told where the starter is in its photo, with a region holding it; the
    # starter, who marked the joiner, is told where its own mark puts the joiner.
    joiners = answer["in_photo"]["joiner"]
    assert joiners["how"] == "solved"
    assert in_region(joiners["region"], s.epipole2)
    starters = answer["in_photo"]["starter"]
    assert starters["how"] == "marked"
    assert np.linalg.norm(np.array(starters["friend"]) - s.epipole1) < 3.0
    assert state["answer_version"] == state["version"]
    assert starter.state()["answer"] == answer  # both phones see the same answer


@pytest.mark.parametrize(
    ("marks", "fewest"),
    [
        ({}, 7),  # nothing marked
        ({"friend_line": "line"}, 6),  # a line through the joiner
        ({"friend": "joiner"}, 3),  # the joiner (5 without the phone cameras)
    ],
)
def test_the_counter_counts_down_to_what_the_solver_needs_from_phones(
    uploaded: Phones, marks: dict[str, str], fewest: int
) -> None:
    starter, joiner = uploaded
    s = scene(7, seed=5)
    drawn = {
        "friend": list(s.epipole1),
        # vertical, through the joiner
        "friend_line": {"a": 1.0, "b": 0.0, "c": -float(s.epipole1[0])},
    }
    mark = {name: drawn[name] for name in marks}
    starter.tap(landmarks=landmarks(s.landmarks1), **mark)
    for n in range(fewest):
        state = joiner.tap(landmarks=landmarks(s.landmarks2[:n])).json()
        assert state["landmarks_needed"] == fewest - n
        assert state["answer"] is None
    state = joiner.tap(landmarks=landmarks(s.landmarks2[:fewest])).json()
    assert state["landmarks_needed"] == 0
    assert state["answer"]["camera_model"] == "pinhole"


def test_either_friend_may_mark_the_other(uploaded: Phones) -> None:
    """The friend who joined sees the one who started and marks them: the starter's phone is
    told where the joiner is, from the same three landmarks."""
    starter, joiner = uploaded
    s = scene(5, seed=21)
    starter.tap(landmarks=landmarks(s.landmarks1[:3]))
    state = joiner.tap(landmarks=landmarks(s.landmarks2[:3]), friend=list(s.epipole2)).json()
    answer = state["answer"]
    assert answer["method"] == "pinhole_epipole"
    starters, joiners = answer["in_photo"]["starter"], answer["in_photo"]["joiner"]
    assert (starters["how"], joiners["how"]) == ("solved", "marked")
    assert in_region(starters["region"], s.epipole1)
    assert joiners["region"] is None  # the joiner tapped their friend: no region to draw
    assert starter.state()["answer"] == answer


def test_a_line_from_either_phone_and_a_point_from_the_other(uploaded: Phones) -> None:
    """A line through the friend answers with six landmarks; once the other phone taps its
    friend as a point, the point answers (three landmarks would do) and the line is not
    needed."""
    starter, joiner = uploaded
    s = scene(6, seed=22)
    through = {"a": 0.0, "b": 1.0, "c": -float(s.epipole2[1])}  # level, through the starter
    starter.tap(landmarks=landmarks(s.landmarks1))
    state = joiner.tap(landmarks=landmarks(s.landmarks2), friend_line=through).json()
    starters, joiners = (state["answer"]["in_photo"][role] for role in ROLES)
    assert state["answer"]["method"] == "pinhole_line"
    assert joiners["how"] == "on_line"
    assert abs(joiners["friend"][1] - s.epipole2[1]) < 1e-6 * abs(s.epipole2[1]) + 3.0
    assert np.linalg.norm(np.array(starters["friend"]) - s.epipole1) < 10.0
    state = starter.tap(landmarks=landmarks(s.landmarks1), friend=list(s.epipole1)).json()
    assert state["answer"]["method"] == "pinhole_epipole"
    assert state["answer"]["in_photo"]["starter"]["how"] == "marked"
    assert in_region(state["answer"]["in_photo"]["joiner"]["region"], s.epipole2)


def test_each_taps_precision_sizes_the_region(uploaded: Phones) -> None:
    """The same taps said to be ten times less precise give a much larger region (ten times
    where the taps alone fix the answer; less where the focal-length prior, which does not
    change, fixes part of it)."""
    starter, joiner = uploaded
    s = scene(8, seed=23)
    axes = []
    for sigma in (0.5, 5.0):
        friend = {"x": s.epipole1[0], "y": s.epipole1[1], "sigma": sigma}
        starter.tapped(landmarks=landmarks(s.landmarks1, sigma=sigma), friend=friend)
        state = joiner.tapped(landmarks=landmarks(s.landmarks2, sigma=sigma))
        axes.append(np.array(state["answer"]["in_photo"]["joiner"]["region"]["axes"]))
    assert np.all(axes[1] > 3 * axes[0])
    assert np.all(axes[1] < 11 * axes[0])


def test_the_lens_a_photo_tells_reaches_the_answer(
    starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """A photo's own EXIF focal length is read by the server; a shrunk photo's comes from
    the phone's form fields; the answer uses each as that camera's focal length."""
    starter_photo = with_exif_focal(temple_photos[0], focal_35mm=31)
    lens = starter.upload(starter_photo, "photo.jpg").json()["lens"]
    assert lens == {"focal_35mm": 31.0, "told_by": "photo"}
    told_by_phone = {"focal_35mm": "44", "make": "Google", "model": "Pixel 7"}
    told = joiner.upload(temple_photos[1], "photo.png", "image/png", told_by_phone)
    assert told.json()["lens"] == {"focal_35mm": 44.0, "told_by": "phone"}
    state = tapped_scene(starter, joiner, scene(5, seed=24))
    assert state["photos"]["starter"]["lens"]["told_by"] == "photo"
    focal = {role: state["answer"]["in_photo"][role]["focal_35mm"] for role in ROLES}
    # Known to 2 %: the fit keeps each within a few percent of what the photo said.
    assert abs(focal["starter"] / 31 - 1) < 0.1
    assert abs(focal["joiner"] / 44 - 1) < 0.1


def with_gravity(phone: Phone, photo: bytes, seen_by: Camera | np.ndarray, **more: str) -> Any:
    """Upload ``photo`` with the phone's gravity reading (the form field three times): a
    down direction, or a scene camera's. A camera's is the temple's vertical (its y axis: any
    world direction read by both phones), and its lens goes as the phone's EXIF would tell
    it (the temple's long lenses: no phone's main camera)."""
    if isinstance(seen_by, Camera):
        more = {"focal_35mm": f"{focal_35mm(seen_by.intrinsics[0, 0], (640, 480)):.1f}"} | more
    down = seen_by.down if isinstance(seen_by, Camera) else seen_by
    gravity = {"gravity": [f"{value:.9f}" for value in down], **more}
    return phone.upload(photo, "photo.png", "image/png", gravity)


def test_both_phones_gravity_gives_the_level_then_a_point(
    starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """Both photos with the phones' gravity: the friend mark alone gives the joiner the level
    the starter is on (a band through the truth), one landmark a point."""
    s = scene(2, seed=30)
    stored = with_gravity(starter, temple_photos[0], s.camera1, gravity_sigma_deg="0.5")
    assert stored.status_code == 200, stored.text
    assert stored.json()["gravity"]["sigma_deg"] == 0.5
    assert np.allclose(stored.json()["gravity"]["down"], s.camera1.down)
    joined = with_gravity(joiner, temple_photos[1], s.camera2)
    assert joined.json()["gravity"]["sigma_deg"] == 1.0
    state = starter.tap(landmarks=[], friend=list(s.epipole1)).json()
    assert state["landmarks_needed"] == 1
    assert state["answer"]["method"] == "pinhole_level"
    seen = state["answer"]["in_photo"]["joiner"]
    assert seen["friend"] is None
    assert seen["level"]
    assert seen["level_halfwidth"] > 0
    assert seen["drawing"]["curve"]["halfwidth"] == pytest.approx(seen["level_halfwidth"], abs=0.01)
    assert distance_to(seen["level"], s.epipole2) <= seen["level_halfwidth"]

    starter.tap(landmarks=landmarks(s.landmarks1[:1]), friend=list(s.epipole1))
    state = joiner.tap(landmarks=landmarks(s.landmarks2[:1])).json()
    assert state["landmarks_needed"] == 0
    assert state["answer"]["method"] == "pinhole_epipole"
    friend = state["answer"]["in_photo"]["joiner"]["friend"]
    assert friend is not None
    # Exact taps; the model puts the principal point at the centre, the temple's is 19 px off.
    assert np.hypot(*(np.array(friend) - s.epipole2)) < 60


def test_both_phones_headings_give_the_stretch_of_the_level(
    starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """Both photos with the phones' gravity and compass heading: the solver is told both
    headings (``used_heading``), and the level the friend mark gives carries the stretch the
    compasses point to, drawn bolder on the band; the truth is on it. One heading is not
    enough: the level comes without a stretch."""
    s = scene(2, seed=30)
    # Any north both phones share: 100 degrees off the scene's, and one said a turn later.
    headings = [f"{s.camera1.heading + 100:.6f}", f"{s.camera2.heading + 100 - 360:.6f}"]
    with_gravity(starter, temple_photos[0], s.camera1)
    joined = with_gravity(joiner, temple_photos[1], s.camera2, heading=headings[1])
    assert joined.json()["heading"] == pytest.approx((s.camera2.heading + 100) % 360)
    state = starter.tap(landmarks=[], friend=list(s.epipole1)).json()
    assert state["answer"]["method"] == "pinhole_level"
    assert state["answer"]["used_heading"] is False
    assert state["answer"]["in_photo"]["joiner"]["level_stretch"] is None

    with_gravity(starter, temple_photos[0], s.camera1, heading=headings[0])
    state = starter.tap(landmarks=[], friend=list(s.epipole1)).json()
    assert state["answer"]["method"] == "pinhole_level"
    assert state["answer"]["used_heading"] is True
    seen = state["answer"]["in_photo"]["joiner"]
    assert seen["level_stretch"]
    assert seen["drawing"]["curve"]["stretch"]
    assert distance_to(seen["level_stretch"], s.epipole2) <= seen["level_halfwidth"]


def test_a_heading_is_kept_with_the_photo_wrapped_to_a_turn(
    starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """The compass heading at the shutter is kept with the photo, in [0, 360), and shown to
    both phones; without gravity it is kept all the same (and unused)."""
    fields = {"heading": "-30", "heading_sigma_deg": "20"}
    stored = starter.upload(temple_photos[0], "photo.png", "image/png", fields)
    assert stored.status_code == 200, stored.text
    assert (stored.json()["heading"], stored.json()["heading_sigma_deg"]) == (330.0, 20.0)
    joined = with_gravity(joiner, temple_photos[1], np.array([0.0, 1.0, 0.0]), heading="725.5")
    assert (joined.json()["heading"], joined.json()["heading_sigma_deg"]) == (5.5, 15.0)
    photos = joiner.state()["photos"]
    assert (photos["starter"]["heading"], photos["starter"]["heading_sigma_deg"]) == (330, 20)
    assert (photos["joiner"]["heading"], photos["joiner"]["heading_sigma_deg"]) == (5.5, 15)
    assert photos["starter"]["gravity"] is None


@pytest.mark.parametrize(
    "fields",
    [
        {"gravity": ["0", "0", "0"]},
        {"gravity": ["0", "1"]},
        {"gravity": ["0", "1", "nan"]},
        {"gravity": ["0", "1", "0"], "gravity_sigma_deg": "45"},
        {"gravity_sigma_deg": "1"},
        {"heading": "nan"},
        {"heading": "inf"},
        {"heading": "north"},
        {"heading": "90", "heading_sigma_deg": "0"},
        {"heading": "90", "heading_sigma_deg": "nan"},
        {"heading_sigma_deg": "15"},
    ],
)
def test_a_reading_that_is_no_direction_is_refused(
    starter: Phone, temple_photos: tuple[bytes, bytes], fields: dict[str, Any]
) -> None:
    refused = starter.upload(temple_photos[0], "photo.png", "image/png", fields)
    assert error_of(refused, 422) == "invalid_request"
    assert starter.state()["photos"]["starter"] is None


def with_exif_focal(png: bytes, *, focal_35mm: int) -> bytes:
    """The photo as a phone's JPEG whose EXIF gives its lens (and a GPS position, which
    must not be kept)."""
    exif = exif_of(make="Apple", GPSLatitudeRef="N")
    exif.get_ifd(ExifTags.IFD.Exif)[ExifTags.Base.FocalLengthIn35mmFilm] = focal_35mm
    return encoded(Image.open(io.BytesIO(png)).convert("RGB"), quality=95, exif=exif)


def test_both_friends_marked_one_landmark_is_enough(uploaded: Phones) -> None:
    """Each sees the other: with phone photos one common landmark fixes the starter (three
    for any two cameras)."""
    starter, joiner = uploaded
    s = scene(3, seed=13)
    starter.tap(landmarks=landmarks(s.landmarks1), friend=list(s.epipole1))
    state = joiner.tap(landmarks=[], friend=list(s.epipole2)).json()
    assert state["landmarks_needed"] == 1
    assert state["answer"] is None
    state = joiner.tap(landmarks=landmarks(s.landmarks2[:1]), friend=list(s.epipole2)).json()
    assert state["landmarks_needed"] == 0
    answer = state["answer"]
    assert answer["method"] == "pinhole_two_epipoles"
    assert answer["camera_model"] == "pinhole"
    # Both marks are used for both answers: each is its own mark, refined by the fit.
    for role, truth in (("starter", s.epipole1), ("joiner", s.epipole2)):
        assert answer["in_photo"][role]["how"] == "marked"
        assert np.linalg.norm(np.array(answer["in_photo"][role]["friend"]) - truth) < 3.0


def test_taps_that_fit_no_phones_are_answered_without_the_camera_model(uploaded: Phones) -> None:
    """The solver falls back to the projective geometry, and says so: four landmarks give
    the curve the starter is on, and the counter asks for the fifth that fixes the spot."""
    starter, joiner = uploaded
    starter.tap(landmarks=landmarks(NO_PHONES_LANDMARKS1), friend=list(NO_PHONES_FRIEND))
    state = joiner.tap(landmarks=landmarks(NO_PHONES_LANDMARKS2[:3])).json()
    assert state["answer"] is None
    assert state["answer_error"]["code"] == "degenerate_configuration"

    state = joiner.tap(landmarks=landmarks(NO_PHONES_LANDMARKS2[:4])).json()
    answer = state["answer"]
    assert answer["method"] == "conic"
    assert answer["camera_model"] == "projective"
    for role in ROLES:  # said to both phones
        told = answer["in_photo"][role]["warnings"][0]
        assert told["code"] == "camera_model_disagrees"
        assert "do not fit two ordinary phone photos" in told["message"]
    assert answer["in_photo"]["joiner"]["curve"] is not None
    assert answer["in_photo"]["joiner"]["friend"] is None
    assert state["landmarks_needed"] == 1  # the curve: one more for a position
    assert starter.state()["landmarks_needed"] == 1

    state = joiner.tap(landmarks=landmarks(NO_PHONES_LANDMARKS2)).json()
    assert state["answer"]["method"] == "five_point_epipole"
    assert state["answer"]["camera_model"] == "projective"
    assert state["landmarks_needed"] == 0


def test_the_reply_to_taps_is_the_state_a_fetch_then_shows(uploaded: Phones) -> None:
    """The taps and their answer are one write: the reply is what the other phone sees."""
    starter, joiner = uploaded
    s = scene(6, seed=3)
    starter.tap(landmarks=landmarks(s.landmarks1), friend=list(s.epipole1))
    for n in (2, 3, 6):  # no answer yet, then answers
        reply = joiner.tap(landmarks=landmarks(s.landmarks2[:n])).json()
        assert reply == joiner.state()
        fetched = starter.state()
        for key in ("version", "answer", "answer_version", "answer_error", "taps"):
            assert fetched[key] == reply[key]
    assert reply["answer"]["method"] == "pinhole_epipole"  # 6 landmarks + e1, phone cameras


def overtaken(
    app: Any, phones: Phones, tapped: int, then: Callable[[], httpx2.Response] | None = None
) -> tuple[dict[str, Any], list[httpx2.Response]]:
    """Five landmarks of ``scene(6, seed=4)`` tapped by the starter, ``tapped`` by the joiner;
    then the joiner taps all six, overtaken: the starter's taps of all six land between the
    joiner's request reading the session and writing its own. The joiner's reply, and what
    was got as it happened: the starter's reply, then (if given) what ``then`` got right
    after the joiner's write, before its request answered the session again."""
    starter, joiner = phones
    s = scene(6, seed=4)
    starter.tap(landmarks=landmarks(s.landmarks1[:5]), friend=list(s.epipole1))
    joiner.tap(landmarks=landmarks(s.landmarks2[:tapped]))
    store = app.state.services.taps.taps
    write = store.put_taps
    got: list[httpx2.Response] = []

    def overtaking(participant: Any, *args: Any, **options: Any) -> Any:
        if got or participant.role != "joiner":
            return write(participant, *args, **options)
        got.append(starter.tap(landmarks=landmarks(s.landmarks1), friend=list(s.epipole1)))
        written = write(participant, *args, **options)
        if then is not None:
            got.append(then())
        return written

    store.put_taps = overtaking
    return joiner.tap(landmarks=landmarks(s.landmarks2)).json(), got


def test_taps_overtaken_by_the_other_phone_are_answered_afresh(app: Any, uploaded: Phones) -> None:
    """The other phone's taps land between reading the session and writing these: the
    answer computed before that would be stale, so the new version is answered again."""
    joiner = uploaded[1]
    reply, sneaked = overtaken(app, uploaded, tapped=4)
    assert sneaked[0].status_code == 200
    # Answered with the starter's 6 landmarks, which came in after the joiner's request did.
    assert reply["answer"]["method"] == "pinhole_epipole"
    assert reply["answer"]["landmark_ids"] == [1, 2, 3, 4, 5, 6]
    assert reply["answer_version"] == reply["version"] == sneaked[0].json()["version"] + 1
    assert reply == joiner.state()
    # Its event cannot tell the starter the count it computed before being overtaken (the
    # starter's phone fetches the state); the answer's event, computed afresh, can.
    events = app.state.services.streams.log.events_after(joiner.session_id, 0)
    told = {(event.type, event.data.get("version")): event.data for event in events}
    assert told["taps", reply["version"]]["landmarks_needed"] is None
    assert told["answer", reply["version"]]["answer"] == reply["answer"]


def test_landmarks_tapped_in_one_photo_only_do_not_count(uploaded: Phones) -> None:
    starter, joiner = uploaded
    s = scene(7)
    starter.tap(landmarks=landmarks(s.landmarks1, [1, 2, 3, 4, 5, 6, 7]), friend=list(s.epipole1))
    state = joiner.tap(landmarks=landmarks(s.landmarks2[[0, 1, 2, 6]], [1, 2, 3, 9])).json()
    assert state["answer"]["method"] == "pinhole_epipole"
    assert state["answer"]["landmark_ids"] == [1, 2, 3]


def test_a_new_photo_clears_its_taps_and_the_answer(
    uploaded: Phones, temple_photos: tuple[bytes, bytes]
) -> None:
    starter, joiner = uploaded
    assert tapped_scene(starter, joiner, scene(5))["answer"] is not None
    assert joiner.upload(temple_photos[1], "again.png").status_code == 200
    state = starter.state()
    assert state["taps"]["joiner"] is None
    assert state["taps"]["starter"] is not None
    assert state["answer"] is None


# --- pictures -------------------------------------------------------------------------


def test_overlays_show_the_answer_on_each_photo(client: TestClient, uploaded: Phones) -> None:
    starter, joiner = uploaded
    before = starter.call("GET", "/overlay/joiner")
    assert error_of(before, 409) == "no_result"
    tapped_scene(starter, joiner, scene(6))
    for role, fmt, magic in (("joiner", "png", b"\x89PNG"), ("starter", "jpeg", b"\xff\xd8\xff")):
        response = joiner.call("GET", f"/overlay/{role}", params={"format": fmt})
        assert response.content.startswith(magic)
        assert response.headers["content-type"] == f"image/{fmt}"
        assert image_of(response).shape == (480, 640, 3)
    again = joiner.call("GET", "/overlay/joiner")
    assert again.headers["content-type"] == "image/jpeg"  # the default for a phone
    assert again.content == joiner.call("GET", "/overlay/joiner").content
    # <img> cannot send headers: the token may come in the query.
    by_query = client.get(joiner.url("/overlay/joiner"), params={"token": joiner.token})
    assert by_query.status_code == 200


def test_an_overlay_renders_the_drawing_the_phone_gets(
    services: Services, uploaded: Phones
) -> None:
    """The overlay is the state's ``in_photo[role].drawing`` rendered on the stored photo:
    the shapes the phone draws as SVG, which are the solver's answer's shapes for that
    photo."""
    starter, joiner = uploaded
    s = scene(6)
    state = tapped_scene(starter, joiner, s)
    snapshot = read_snapshot(services.database, joiner.session_id)
    stored = None if snapshot is None else StoredAnswer.read(snapshot.answer)
    assert stored is not None
    assert stored.solution is not None
    assert stored.order is not None
    result = SolveResult.model_validate(stored.solution)
    for role, tapped in zip(ROLES, (s.landmarks1, s.landmarks2), strict=True):
        overlay = image_of(joiner.call("GET", f"/overlay/{role}", params={"format": "png"}))
        pixels = image_of(joiner.call("GET", f"/photo/{role}"))
        number = stored.order.number(role)
        drawing = AnswerDrawing.model_validate(state["answer"]["in_photo"][role]["drawing"])
        # render draws on a copy of the photo's pixels (astype copies)
        assert np.array_equal(overlay, render(pixels.astype(np.uint8), drawing, photo=number))
        labels = state["answer"]["landmark_ids"]
        shapes = answer_drawing(
            result, photo=number, size=(640, 480), landmarks=tapped, labels=labels
        )
        # The same shapes, to the 0.01 px the state keeps.
        assert drawing.model_dump_json() == shapes.model_dump_json()


def test_a_live_frame_gives_the_turn_since_the_photo_and_is_not_kept(uploaded: Phones) -> None:
    """ "Show me" re-anchors: a frame of the live view (here the stored photo as a phone
    turned 3 degrees would see it, 480 px wide) gives the turn; a frame of nothing is refused
    with the solver's code; before an answer there is no focal length to match with."""
    starter, joiner = uploaded
    frame = {"frame": ("frame.jpg", b"", "image/jpeg")}
    before = joiner.call("POST", "/reanchor", files=frame)
    assert error_of(before) == "no_result"
    state = tapped_scene(starter, joiner, scene(6))
    focal = state["answer"]["in_photo"]["joiner"]["focal_px"]
    pixels = image_of(joiner.call("GET", "/photo/joiner"))
    height, width = pixels.shape[:2]
    k_photo = np.array([[focal, 0, width / 2], [0, focal, height / 2], [0, 0, 1.0]])
    k_frame = np.diag([0.75, 0.75, 1.0]) @ k_photo
    turn = cv2.Rodrigues(np.array([0.2, 1.0, 0.1]) / np.linalg.norm([0.2, 1.0, 0.1]) * 0.05)[0]
    seen = cv2.warpPerspective(
        pixels, k_frame @ turn @ np.linalg.inv(k_photo), (width * 3 // 4, height * 3 // 4)
    )
    ok, jpeg = cv2.imencode(".jpg", seen, [cv2.IMWRITE_JPEG_QUALITY, 90])
    assert ok
    frame = {"frame": ("frame.jpg", jpeg.tobytes(), "image/jpeg")}
    found = joiner.ok("POST", "/reanchor", files=frame).json()
    off = cv2.Rodrigues(np.array(found["rotation"]) @ turn.T)[0]
    assert np.degrees(np.linalg.norm(off)) < 0.2
    assert found["frame_focal_px"] == pytest.approx(0.75 * focal, rel=0.01)
    assert found["degrees"] == pytest.approx(np.degrees(0.05), abs=0.2)
    blank = cv2.imencode(".jpg", np.full_like(seen, 100))[1].tobytes()
    refused = joiner.call("POST", "/reanchor", files={"frame": ("frame.jpg", blank, "image/jpeg")})
    assert error_of(refused, 422) == "no_solution"
    assert "photo" in refused.json()["error"]["message"]
    garbage = {"frame": ("frame.jpg", b"not a picture", "image/jpeg")}
    assert error_of(joiner.call("POST", "/reanchor", files=garbage)) == ("invalid_photo")


def test_an_overlay_asked_for_while_the_answer_is_renewed_is_drawn(
    app: Any, uploaded: Phones
) -> None:
    """The joiner's taps are overtaken by the starter's: they are written without their
    (stale) answer, and the answer for the session as it now is comes a moment later. An
    overlay asked for in that moment is answered then and there, not refused."""
    starter, joiner = uploaded
    reply, got = overtaken(app, uploaded, 5, then=lambda: starter.call("GET", "/overlay/joiner"))
    assert image_of(got[1]).shape == (480, 640, 3)
    assert reply["answer"]["landmark_ids"] == [1, 2, 3, 4, 5, 6]
    assert reply == joiner.state()


def test_the_other_phone_gets_a_crop_of_each_landmark(uploaded: Phones) -> None:
    starter, joiner = uploaded
    s = scene(3)
    starter.tap(landmarks=landmarks(s.landmarks1))
    crop = joiner.call("GET", "/landmarks/starter/2/crop")
    assert crop.headers["content-type"] == "image/jpeg"
    image = image_of(crop)
    assert image.shape[0] == image.shape[1] > 50
    missing = joiner.call("GET", "/landmarks/starter/9/crop")
    assert error_of(missing, 404) == "landmark_not_found"


# --- the end --------------------------------------------------------------------------


def test_delete_now_removes_everything_for_both_phones(
    services: Services, uploaded: Phones
) -> None:
    starter, joiner = uploaded
    assert joiner.call("DELETE").status_code == 204
    for phone in (starter, joiner):
        assert phone.call("GET").status_code == 401
    with services.database.engine.connect() as connection:
        for table in ("sessions", "participants", "photos", "events"):
            assert connection.exec_driver_sql(f"SELECT COUNT(*) FROM {table}").scalar() == 0


def test_expired_sessions_are_swept_away(
    services: Services, uploaded: Phones, clock: FakeClock
) -> None:
    starter, _ = uploaded
    assert services.pairing.sweep() == []
    clock.advance(7201)
    assert starter.call("GET").status_code == 401
    assert services.pairing.sweep() == [starter.session_id]
    with services.database.engine.connect() as connection:
        assert connection.exec_driver_sql("SELECT COUNT(*) FROM photos").scalar() == 0


def test_the_state_says_who_is_there(starter: Phone, joiner: Phone) -> None:
    state = joiner.state()
    assert state["you"] == "joiner"
    assert state["join_code"] is None  # only the starter is shown the code
    assert state["participants"]["starter"] == {"joined": True, "online": False}
    assert state["photos"] == {"starter": None, "joiner": None}
    version = state["version"]
    assert starter.state()["version"] == version


def test_each_phone_can_fetch_the_stored_photos(
    client: TestClient, starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """The app shows the stored photo to tap on: exactly the pixels taps refer to."""
    missing = starter.call("GET", "/photo/joiner")
    assert error_of(missing, 404) == "photo_not_found"
    photos_uploaded(starter, joiner, temple_photos)
    for role in ("starter", "joiner"):
        stored = client.get(starter.url(f"/photo/{role}"), params={"token": starter.token})
        assert stored.headers["content-type"] == "image/jpeg"
        assert image_of(stored).shape == (480, 640, 3)


def test_the_same_photo_sent_twice_at_once_is_stored_once(
    starter: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """A phone on a bad network retries an upload that is still in flight."""
    with ThreadPoolExecutor(4) as pool:
        answers = list(pool.map(lambda _: starter.upload(temple_photos[0], "p.png"), range(4)))
    assert [a.status_code for a in answers] == [200] * 4
    assert starter.state()["photos"]["starter"] == stored_photo(640, 480)
