"""Guided tapping, in each engine: once there is an answer, the phone that still has to
find a landmark sees its band (where it must be), a tap far outside the band is flagged at
once, and where the other photo's patch is found along the band for sure, a ring suggests
the spot and one tap takes it.

Bands and flags on the temple photos; the suggestion on a rendered hall seen from both ends
(``testbed.venue``), whose photos have the texture a search needs.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest

from testbed.browser import play
from testbed.browser.phone import Phone, expect
from testbed.venue import rendered_pair

pytestmark = pytest.mark.engines("chromium", "webkit")


def inside(outline: list[list[float]], point: np.ndarray) -> bool:
    polygon = np.array(outline, dtype=np.float32).reshape(-1, 1, 2)
    return cv2.pointPolygonTest(polygon, (float(point[0]), float(point[1])), False) >= 0


def find_boxes(page: Phone) -> dict[str, tuple[float, float, float, float]]:
    """Where the find prompt, its "Can't see it" and the photo's stage are, client px."""
    return {
        "prompt": page.locator("section.prompt").box(),
        "skip": page.get_by_test_id("skip-landmark").box(),
        "stage": page.locator(".stage").box(),
    }


def band_of(page: Phone, role: str, landmark: int) -> dict[str, Any]:
    bands = play.answer_in(page, role)["bands"]
    return next(band for band in bands if band["id"] == landmark)


def test_the_band_shows_where_to_look_and_a_tap_far_from_it_is_flagged(
    server: str, pixel: Phone, iphone: Phone, screenshots: Path
) -> None:
    starter, joiner = play.start_and_join(server, pixel, iphone, photos=True)
    truth = play.scene(7, seed=16)
    play.marked_and_found(starter, joiner, truth.epipole1, truth.landmarks1, truth.landmarks2[:5])

    # The answer is in: #6's band is drawn on the joiner's photo, and holds the landmark.
    drawn = joiner.get_by_test_id("landmark-band")
    expect(drawn).to_have_attribute("data-id", "6")
    band = band_of(joiner, "joiner", 6)
    assert inside(band["outline"], truth.landmarks2[5])
    assert play.answer_in(starter, "starter")["bands"] == []
    joiner.screenshot(path=screenshots / "10-band-joiner.png")

    # #6 tapped 60 px across its band: flagged at once, in words and with a re-check.
    (x0, y0), (x1, y1) = band["start"], band["end"]
    across = np.array([y0 - y1, x1 - x0]) / np.hypot(x1 - x0, y1 - y0)
    wrong = truth.landmarks2[5] + 60 * across
    if not (0 < wrong[0] < 640 and 0 < wrong[1] < 480):
        wrong = truth.landmarks2[5] - 60 * across
    assert not inside(band["outline"], wrong)
    joiner.tap_photo(*wrong)
    play.saved(joiner)
    flagged = joiner.get_by_test_id("warning").filter(has_text="#6")
    expect(flagged).to_have_count(1)  # the flag's sentence, or the fit's if it left #6 out
    expect(joiner.get_by_test_id("recheck").filter(has_text="#6")).to_be_visible()
    joiner.screenshot(path=screenshots / "11-flag-joiner.png")

    # Re-checked (its chip selects it), deleted and tapped where it belongs: the flag goes.
    joiner.get_by_test_id("recheck").filter(has_text="#6").tap()
    joiner.get_by_test_id("delete-landmark").tap()
    expect(joiner.get_by_test_id("find-prompt")).to_have_attribute("data-id", "6")
    joiner.tap_photo(*truth.landmarks2[5])
    play.saved(joiner)
    expect(joiner.get_by_test_id("recheck")).to_have_count(0)
    assert play.answer_in(joiner, "joiner")["misfits"] == []


# The suggestion is the server's; its ring and the one tap are the band test's drawing and
# tapping, which runs in WebKit too: in Chromium only, to keep make test within 15 minutes.
@pytest.mark.engines("chromium")
def test_a_sure_match_is_suggested_and_one_tap_takes_it(
    server: str, pixel: Phone, iphone: Phone, screenshots: Path, tmp_path: Path
) -> None:
    hall = rendered_pair(24)
    s = hall.scene
    starter, joiner = play.start_and_join(server, pixel, iphone)
    shots = ((starter, hall.photo1, s.image_size1), (joiner, hall.photo2, s.image_size2))
    for role, (page, photo, size) in zip(("starter", "joiner"), shots, strict=True):
        path = tmp_path / f"{role}.jpg"
        cv2.imwrite(str(path), photo, [cv2.IMWRITE_JPEG_QUALITY, 92])
        play.upload(page, path, size)
    play.marked_and_found(starter, joiner, s.epipole1, s.landmarks1[:12], s.landmarks2[:6])

    # The first landmark past the answer for which the search is sure: its ring, then a tap.
    diagonal = float(np.hypot(*s.image_size2))
    for landmark in range(7, 13):
        prompt = joiner.get_by_test_id("find-prompt")
        expect(prompt).to_have_attribute("data-id", str(landmark))
        before = find_boxes(joiner)
        expect(prompt).to_have_attribute("data-suggestion", re.compile("^(shown|none)$"))
        if prompt.get_attribute("data-suggestion") == "shown":
            break
        play.find_landmarks(joiner, s.landmarks2[landmark - 1 : landmark], first_id=landmark)
    else:
        pytest.fail("no suggestion for landmarks 7-12")
    suggested = joiner.get_by_test_id("suggested-spot")
    expect(suggested).to_have_attribute("data-id", str(landmark))
    spot = np.array(suggested.numbers("x", "y"))
    assert np.hypot(*(spot - s.landmarks2[landmark - 1])) < 0.01 * diagonal
    joiner.screenshot(path=screenshots / "12-suggestion-joiner.png")
    # Both buttons whole in the prompt, and the photo and "Can't see it" where they were when
    # the step began: a suggestion coming moves nothing a finger may be about to tap.
    boxes = find_boxes(joiner)
    left, top, right, bottom = boxes["prompt"]
    for x0, y0, x1, y1 in (joiner.get_by_test_id("accept-suggestion").box(), boxes["skip"]):
        assert left - 0.5 <= x0 < x1 <= right + 0.5, (boxes["prompt"], (x0, x1))
        assert top - 0.5 <= y0 < y1 <= bottom + 0.5, (boxes["prompt"], (y0, y1))
    assert boxes["stage"] == pytest.approx(before["stage"], abs=0.5)
    assert boxes["skip"] == pytest.approx(before["skip"], abs=0.5)
    joiner.get_by_test_id("accept-suggestion").tap()
    play.saved(joiner)
    taps = play.session_state(joiner)["taps"]["joiner"]["landmarks"]
    taken = next(tap for tap in taps if tap["id"] == landmark)
    assert (taken["x"], taken["y"]) == pytest.approx(
        tuple(spot), abs=0.051
    )  # taps are sent to 0.1 px
