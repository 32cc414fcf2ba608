"""Guidance once there is an answer: the band where each landmark the other phone tapped
must be, a flag on a tap far outside its band, and a suggested spot (docs/api.md)."""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np
import pytest
from phones import Phones, error_of, landmarks, photos_uploaded, scene, tapped_scene

from testbed.client import Phone
from testbed.venue import RenderedPair, rendered_pair

# What these check is the image matching and the bands, computed from what storage gives
# back; storing taps and photos on each database is test_sessions' and test_kept_photos'.
pytestmark = pytest.mark.databases("sqlite")


def inside(band: dict[str, Any], point: Any) -> bool:
    """Whether ``point`` (x, y) lies in a band's outline."""
    outline = np.array(band["outline"], dtype=np.float32).reshape(-1, 1, 2)
    return cv2.pointPolygonTest(outline, (float(point[0]), float(point[1])), False) >= 0


def answered(starter: Phone, joiner: Phone, photos: tuple[bytes, bytes]) -> Any:
    """Both photos, the starter's 7 landmarks and friend mark, the joiner's first 5."""
    photos_uploaded(starter, joiner, photos)
    s = scene(7, seed=4)
    tapped_scene(starter, joiner, s, 5)
    return s


def test_a_landmark_only_the_other_phone_tapped_gets_a_band_holding_it(
    starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    s = answered(starter, joiner, temple_photos)
    answer = joiner.state()["answer"]
    bands = {band["id"]: band for band in answer["in_photo"]["joiner"]["bands"]}
    assert set(bands) == {6, 7}
    for i in (6, 7):
        assert inside(bands[i], s.landmarks2[i - 1])
        assert 0.9 <= bands[i]["level"] < 1
        # A band, not the whole photo: a few percent of its 640 x 480 area.
        area = cv2.contourArea(np.array(bands[i]["outline"], dtype=np.float32))
        assert 0 < area < 0.1 * 640 * 480
    # The starter has tapped every landmark the joiner has: nothing to find.
    assert answer["in_photo"]["starter"]["bands"] == []
    assert answer["in_photo"]["joiner"]["misfits"] == []


def test_a_tap_far_outside_its_band_is_flagged_until_it_is_moved(
    starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    s = answered(starter, joiner, temple_photos)
    band = next(b for b in joiner.state()["answer"]["in_photo"]["joiner"]["bands"] if b["id"] == 6)
    # Across the band, 60 px from the truth: a plausible finger on the wrong window.
    (x0, y0), (x1, y1) = band["start"], band["end"]
    across = np.array([y0 - y1, x1 - x0]) / np.hypot(x1 - x0, y1 - y0)
    wrong = s.landmarks2[5] + 60 * across
    assert not inside(band, wrong)
    state = joiner.tap(landmarks=landmarks(np.vstack([s.landmarks2[:5], wrong]))).json()
    mine = state["answer"]["in_photo"]["joiner"]
    assert mine["misfits"] == [6]
    # One sentence names it: the flag's, or the fit's when it left the tap out.
    sentences = [w["message"] for w in mine["warnings"] if w.get("landmark") == 6]
    assert len(sentences) == 1
    assert sentences[0].startswith(
        "#6 does not fit the others" if 6 not in state["answer"]["suspects"] else "Landmark #6"
    )
    assert state["answer"]["in_photo"]["starter"]["misfits"] == []

    # Unchanged, it stays flagged while the other phone changes its own taps.
    state = starter.tap(landmarks=landmarks(s.landmarks1[:6]), friend=list(s.epipole1)).json()
    assert state["answer"]["in_photo"]["joiner"]["misfits"] == [6]

    # Moved to the truth, it fits.
    state = joiner.tap(landmarks=landmarks(s.landmarks2[:6])).json()
    assert state["answer"]["in_photo"]["joiner"]["misfits"] == []
    told = state["answer"]["in_photo"]["joiner"]["warnings"]
    assert not any("does not fit" in w["message"] for w in told)


def test_a_tap_inside_its_band_is_not_flagged(
    starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    s = answered(starter, joiner, temple_photos)
    state = joiner.tap(landmarks=landmarks(s.landmarks2[:6] + 1.5)).json()
    assert state["answer"]["in_photo"]["joiner"]["misfits"] == []


@pytest.fixture(scope="module")
def hall() -> RenderedPair:
    """A rendered hall seen from both ends, as the server stores phone photos."""
    return rendered_pair(24)


def hall_tapped(starter: Phone, joiner: Phone, hall: RenderedPair, found: int) -> Any:
    """The hall's photos (JPEG, as a phone's), every landmark and the friend tapped by the
    starter, the first ``found`` by the joiner: the joiner's state."""
    for phone, photo in ((starter, hall.photo1), (joiner, hall.photo2)):
        ok, jpeg = cv2.imencode(".jpg", photo, [cv2.IMWRITE_JPEG_QUALITY, 90])
        assert ok
        assert phone.upload(jpeg.tobytes()).status_code == 200
    return tapped_scene(starter, joiner, hall.scene, found)


def test_suggested_spots_are_where_the_landmarks_are(
    starter: Phone, joiner: Phone, hall: RenderedPair
) -> None:
    """In a hall: the starter has tapped its friend and every landmark, the joiner the first
    6. Spots are suggested for some of the others (the corners of boxes on the floor and of
    a stage, each photo showing other faces of them), at the landmarks (within 1 % of the
    photo's diagonal). How often a suggestion is right over many halls is measured by
    `make bench-suggest` (docs/suggestions.md); this checks the service end to end."""
    state = hall_tapped(starter, joiner, hall, 6)
    s = hall.scene
    count = len(s.points)
    version = state["answer_version"]
    to_find = range(7, count + 1)
    bands = state["answer"]["in_photo"]["joiner"]["bands"]
    assert {band["id"] for band in bands} == set(to_find)
    diagonal = float(np.hypot(*s.image_size2))
    errors = []
    for i in to_find:
        url = f"/landmarks/joiner/{i}/suggestion"
        body = joiner.ok("GET", url).json()
        assert (body["id"], body["answer_version"]) == (i, version)
        if body["spot"] is not None:
            spot = np.array([body["spot"]["x"], body["spot"]["y"]])
            errors.append(float(np.hypot(*(spot - s.landmarks2[i - 1]))))
        # Asked again (a phone reconnecting): the same reply, from the kept search.
        assert joiner.call("GET", url).json() == body
    assert len(errors) >= 2
    assert max(errors) < 0.01 * diagonal


def test_a_taken_suggestion_is_a_tap_like_any_other_flagged_when_it_does_not_fit(
    starter: Phone, joiner: Phone, hall: RenderedPair
) -> None:
    """The phone sends a suggested spot taken with one tap as a tap (with a suggestion's
    precision, frontend/src/guidance.ts). Taken under the answer it was found for, it fits.
    Taken after the other phone has moved that landmark elsewhere (a suggestion shown
    before the answer changed), it does not fit the others, and the reply to that very tap
    flags it."""
    found = 6
    hall_tapped(starter, joiner, hall, found)
    s = hall.scene
    spot = None
    for i in range(found + 1, len(s.points) + 1):
        body = joiner.call("GET", f"/landmarks/joiner/{i}/suggestion").json()
        if body["spot"] is not None:
            spot = body["spot"]
            break
    assert spot is not None
    taken = [*landmarks(s.landmarks2[:found]), {"id": i, **spot, "sigma": 4.0}]

    state = joiner.tap(landmarks=taken).json()
    assert state["answer"]["in_photo"]["joiner"]["misfits"] == []

    # The joiner lets it go; the starter moves #i onto the landmark whose epipolar line
    # passes farthest from the spot; then the joiner takes the spot shown before.
    joiner.tap(landmarks=landmarks(s.landmarks2[:found]))
    lines = np.column_stack([s.landmarks1, np.ones(len(s.points))]) @ s.fundamental.T
    lines /= np.hypot(lines[:, 0], lines[:, 1])[:, None]
    away = int(np.argmax(np.abs(lines @ [spot["x"], spot["y"], 1.0])))
    moved = s.landmarks1.copy()
    moved[i - 1] = s.landmarks1[away]
    starter.tap(landmarks=landmarks(moved), friend=list(s.epipole1))
    state = joiner.tap(landmarks=taken).json()
    assert state["answer"]["in_photo"]["joiner"]["misfits"] == [i]
    told = state["answer"]["in_photo"]["joiner"]["warnings"]
    assert any(f"#{i}" in warning["message"] for warning in told)


def test_a_suggestion_needs_an_answer_and_a_landmark_to_find(uploaded: Phones) -> None:
    starter, joiner = uploaded
    s = scene(7, seed=4)
    starter.tap(landmarks=landmarks(s.landmarks1[:2]), friend=list(s.epipole1))
    early = joiner.call("GET", "/landmarks/joiner/1/suggestion")
    assert (early.status_code, error_of(early)) == (409, "no_result")
    starter.tap(landmarks=landmarks(s.landmarks1), friend=list(s.epipole1))
    joiner.tap(landmarks=landmarks(s.landmarks2[:5]))
    missing = joiner.call("GET", "/landmarks/starter/6/suggestion")
    assert (missing.status_code, error_of(missing)) == (404, "landmark_not_found")
