"""Nothing on top of the answer, in each engine: wherever the friend is in the photo (its top,
its bottom, its four corners), the frame the phone draws lands clear of every word and
control over the photo, with the phone upright and on its side.

The scene is built for the test: the joiner, upright, photographs the hall in portrait (a
photo as tall as the view, so the status over the photo's top has something to cover); six
landmarks stand between the friends; the starter (over the API) stands wherever the test
puts them, and taps the landmarks and the joiner where its camera sees them. Moving the
starter moves the joiner's answer without a tap of the joiner's.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import httpx2
import numpy as np
import pytest
from PIL import Image

from testbed.browser import play
from testbed.browser.phone import Phone, expect
from testbed.browser.screen import OVERLAID
from testbed.client import numbered
from testbed.scenes import Camera, Scene, in_photo, look_at

pytestmark = [pytest.mark.engines("chromium", "webkit"), pytest.mark.turns]

# The joiner's portrait photo and the starter's landscape one: sizes (px) and focal lengths
# (px): a phone's main camera (about 30 and 24 mm equivalent).
JOINER_SIZE = (1200, 1600)
STARTER_SIZE = (1600, 1200)
JOINER_FOCAL = 1400.0
STARTER_FOCAL = 1100.0
# Where the landmarks are in the joiner's photo (fractions of its sides), and how far, m.
LANDMARKS = np.array([[0.3, 0.35], [0.7, 0.3], [0.5, 0.5], [0.25, 0.7], [0.75, 0.65], [0.45, 0.8]])
DEPTHS = np.array([14.0, 20.0, 17.0, 22.0, 15.0, 19.0])
# The starter's distance, m, and where they appear in the joiner's photo (fractions).
DISTANCE = 40.0
PLACES = {
    "top": (0.5, 0.08),
    "top left": (0.08, 0.08),
    "top right": (0.92, 0.08),
    "bottom": (0.5, 0.92),
    "bottom left": (0.08, 0.92),
    "bottom right": (0.92, 0.92),
}

# How long the view may take to settle: the answer's glide, and one more if the status grows.
SETTLE_S = 5.0


def intrinsics(focal: float, size: tuple[int, int]) -> np.ndarray:
    return np.array([[focal, 0.0, size[0] / 2], [0.0, focal, size[1] / 2], [0.0, 0.0, 1.0]])


JOINER = Camera(intrinsics(JOINER_FOCAL, JOINER_SIZE), np.eye(3), np.zeros(3))
POINTS = (
    np.linalg.solve(
        JOINER.intrinsics, np.column_stack([LANDMARKS * JOINER_SIZE, np.ones(len(DEPTHS))]).T
    ).T
    * DEPTHS[:, None]
)


def starter_at(place: tuple[float, float]) -> Scene:
    """The scene with the starter where the joiner's photo shows them at ``place``, aimed
    at the landmarks and the joiner."""
    pixel = np.array([place[0] * JOINER_SIZE[0], place[1] * JOINER_SIZE[1], 1.0])
    ray = np.linalg.solve(JOINER.intrinsics, pixel)
    centre = DISTANCE * ray / np.linalg.norm(ray)
    seen = np.vstack([POINTS, np.zeros((1, 3))])
    starter = Camera(intrinsics(STARTER_FOCAL, STARTER_SIZE), *look_at(centre, seen.mean(axis=0)))
    assert in_photo(starter, seen, STARTER_SIZE, margin=0.03).all(), place
    return Scene(starter, JOINER, POINTS, STARTER_SIZE, JOINER_SIZE)


def plain_photo(size: tuple[int, int], path: Path) -> Path:
    """A photo of ``size`` (the answer depends on the taps alone): a dim gradient."""
    ramp = np.linspace(40, 110, size[0], dtype=np.uint8)
    Image.fromarray(np.tile(ramp, (size[1], 1))).convert("RGB").save(path)
    return path


def starter_taps(scene: Scene) -> dict[str, Any]:
    return {"friend": scene.epipole1, "landmarks": numbered(scene.landmarks1)}


def overlaps(a: Sequence[float], b: Sequence[float]) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def clear_of_everything(phone: Phone, where: str) -> None:
    """Once the view has settled (the status may grow after the answer: the view then
    moves again), no overlaid element's box meets the frame's."""
    expect(phone.get_by_test_id("answer-frame")).to_be_visible()

    def covering() -> tuple[Sequence[float], list[Any]]:
        """The frame's box (its brackets and label) and the overlaid elements it meets."""
        phone.view_box()  # settled: not gliding, nor about to
        frame = phone.get_by_test_id("answer-frame").box()
        return frame, [item for item in phone.evaluate(OVERLAID) if overlaps(frame, item[1:])]

    what = f"the frame clear, the friend at the {where}"
    phone.wait_until(covering, lambda seen: not seen[1], what, timeout=SETTLE_S)


def test_the_frame_lands_clear_of_every_word_and_control(
    api: httpx2.Client, iphone: Phone, tmp_path: Path
) -> None:
    starter = play.joined_by_link(api, iphone, plain_photo(STARTER_SIZE, tmp_path / "starter.png"))
    play.upload(iphone, plain_photo(JOINER_SIZE, tmp_path / "joiner.png"), JOINER_SIZE)
    # The first answer elsewhere: each place below is then a new one, brought into view.
    starter.tapped(**starter_taps(starter_at((0.6, 0.45))))
    play.cannot_see(iphone)
    play.find_landmarks(iphone, JOINER.project(POINTS))

    upright = iphone.evaluate("() => [innerWidth, innerHeight]")
    for where, place in PLACES.items():
        truth = starter_at(place).epipole2
        starter.tapped(**starter_taps(starter_at(place)))

        def moved(truth: np.ndarray = truth) -> bool:
            """The joiner's answer is where the starter now is."""
            return bool(np.linalg.norm(play.reported_position(iphone)[0] - truth) < 40)

        iphone.wait_for(moved, f"the answer at the {where}")
        clear_of_everything(iphone, f"the {where}, upright")
        iphone.resize(upright[1], upright[0])
        clear_of_everything(iphone, f"the {where}, on its side")
        iphone.resize(*upright)
