"""Fingers on the photo, in each engine: a tap, a landmark dragged under the loupe, a pinch
and a two-finger pan, all as Pointer Events of type "touch" (the app's one input path,
frontend/src/pointers.ts).

Chromium gets real touch input through the DevTools protocol; WebKitGTK's driver has none
(docs/browsers.md), so there the page dispatches the fingers' pointer events itself
(``webkit_phone.FINGERS``). Either way the app reads a finger, not a mouse: the tap is
aimed as a finger's, and the loupe shows while it presses.
"""

from __future__ import annotations

import pytest

from testbed.browser import play
from testbed.browser.phone import Phone, expect

pytestmark = pytest.mark.engines("chromium", "webkit")

SPOT = (200.0, 200.0)  # photo px, where the landmark is placed
DRAG_CSS = 60.0


def transform(phone: Phone) -> tuple[float, float, float]:
    scale, tx, ty = phone.get_by_test_id("photo-view").numbers("scale", "tx", "ty")
    return scale, tx, ty


def landmarks(phone: Phone) -> list[dict[str, float]]:
    play.saved(phone)
    found: list[dict[str, float]] = play.session_state(phone)["taps"]["starter"]["landmarks"]
    return found


def test_fingers_tap_drag_pinch_and_pan(server: str, pixel: Phone, iphone: Phone) -> None:
    starter, _ = play.start_and_join(server, iphone, pixel, photos=True)
    play.cannot_see(starter)
    fitted = play.view_scale(starter)

    # A tap of the finger: placed, with a finger's precision (a mouse's is the loupe's).
    starter.touch("down", [starter.photo_to_screen(*SPOT)])
    starter.touch("up")
    label = starter.locator('[data-testid="landmark"][data-id="1"]')
    expect(label).to_be_visible()
    (placed,) = landmarks(starter)
    # WebKit's pointer events carry whole CSS px: the spot is that close.
    assert (placed["x"], placed["y"]) == pytest.approx(SPOT, abs=1 / fitted)
    assert placed["sigma"] == pytest.approx(play.tap_sigma(fitted, "chromium"), abs=0.01)

    # Its label dragged: the loupe shows while the finger presses, the landmark follows it.
    x, y = label.centre()
    starter.drag((x, y), (x + DRAG_CSS, y))
    expect(starter.locator("canvas.loupe")).to_be_visible()
    starter.touch("up")
    expect(starter.locator("canvas.loupe")).to_have_count(0)
    (moved,) = landmarks(starter)
    assert moved["x"] == pytest.approx(placed["x"] + DRAG_CSS / fitted, abs=0.2)
    assert moved["y"] == pytest.approx(placed["y"], abs=0.2)

    # Two fingers spread: the photo zooms about them, and nothing is placed.
    middle = starter.photo_to_screen(320, 240)
    starter.pinch(middle, 2.5)
    scale, tx, ty = transform(starter)
    assert scale == pytest.approx(2.5 * fitted, rel=0.05)
    left, top, _, _ = starter.get_by_test_id("photo-view").box()
    # The photo point that was under the fingers' midpoint is still there.
    assert left + tx + scale * 320 == pytest.approx(middle[0], abs=2)
    assert top + ty + scale * 240 == pytest.approx(middle[1], abs=2)

    # Two fingers moved together pan the zoomed photo.
    fingers = [(middle[0] - 30, middle[1]), (middle[0] + 30, middle[1])]
    starter.touch("down", fingers)
    for k in range(1, 6):
        starter.touch("move", [(fx + 8 * k, fy + 6 * k) for fx, fy in fingers])
    starter.touch("up")
    panned = transform(starter)
    assert panned[0] == pytest.approx(scale, rel=0.01)
    assert (panned[1] - tx, panned[2] - ty) == pytest.approx((40, 30), abs=1)
    assert len(landmarks(starter)) == 1
    expect(starter.get_by_test_id("friend-mark")).to_have_count(0)
