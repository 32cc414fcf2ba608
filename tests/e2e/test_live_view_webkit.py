"""Show me, in WebKit (WebKitGTK's MiniBrowser, Safari's engine): the same geometry as the
Chromium test (test_live_view.py), with what WebKitGTK can give.

- **The camera.** MiniBrowser's mock camera (``--enable-mock-capture-devices``) shows a
  pattern of its own and plays no file: the joiner's photo is a frame of that pattern,
  taken with the in-app camera. The answer needs no picture, only taps: the starter's are
  the temple scene's, and the joiner's are the scene's landmarks in the joiner's camera
  (640 x 480), scaled about the centre into the mock photo (2560 x 1440, landscape: 3 times,
  the scene's frame in the middle of the wider one). A photo so scaled is a camera with its
  focal length scaled and its centre where the app assumes it; the lens prior is in 35 mm
  terms of the photo's diagonal, which the answer's own focal length then says.
- **The orientation.** WebKitGTK has no orientation sensor, no RelativeOrientationSensor
  and no DeviceOrientationEvent: the test dispatches ``deviceorientation`` events itself,
  every 16 ms as iOS sends them (alpha, beta, gamma: the phone upright is beta 90, turned
  right by t is alpha -t), a ``DeviceOrientationEvent`` where the engine has one, else a
  plain ``Event`` with the same fields. The app reads them as it reads iOS's
  (live/sensor.ts), from the in-app camera's shutter on.
- **The motion.** Nor has it a motion sensor: ``WebKitPhone.hold_still`` dispatches a still
  phone's ``devicemotion`` events, and the test plays a walk the same way.

Checked: the marker drawn where the answer's friend projects once the phone has turned
(within 1 degree, against the truth computed here from the answer alone: 0.000 degrees off,
the angles being exact where Chromium's quaternion is rounded); an out-of-view turn shows
the arrow saying which way, and the frame is gone; two minutes after the shutter by the
page's clock the view says it may have drifted; a walk is said; Re-align sends a still
frame of the mock camera to the real server's re-anchoring, which refuses it (the mock's
pattern is no photo of a hall; refused in every run so far): said, the anchor and the
marker unmoved.

What WebKitGTK cannot give, so not tested here (docs/browsers.md):
- **The 1 s opening.** The mock camera's stream is given about 0.2-0.4 s after the tap,
  but its first frame comes 0.5-1.6 s after that; the app's part, from that frame to the
  marker, is held to the 1 s (0.1-0.6 s measured), the whole only in Chromium.
- **The video's focal length.** The mock photo is 2560 x 1440 and the live video 1920 x
  1440: a drawing, no lens, so nothing says what field of view either has. The truth here
  takes the video's focal length by the app's own rule (the photo's, scaled by the long
  sides), so this checks the turn (direction and amount, read from DeviceOrientation's
  angles), not the focal length, which the Chromium test checks on a filmed photo.
- **A matched Align**, for the same reason; the Chromium test plays the endpoint.
"""

from __future__ import annotations

import math

import httpx2
import numpy as np
import pytest

from testbed.browser import play
from testbed.browser.phone import Phone, expect
from testbed.browser.play import ASK_MOTION, still_reading
from testbed.browser.show_me import (
    FILM_DIAGONAL_MM,
    OPENING_BOUND_MS,
    answered,
    drifted,
    hold_turned,
    placed_marker,
    show_me,
    video_on_screen,
)
from testbed.opening import OPENING_STEPS

pytestmark = pytest.mark.engines("webkit")

# The temple scene's photos are 640 x 480: the landmarks' pixels are in that frame.
SCENE_SIZE = (640.0, 480.0)

WALK_SECONDS = 6.0
# A walk for `seconds`: the body rising and falling 2 m/s^2 twice a second along the upright
# phone's y, a motion event every 16 ms (the still phone's events stop meanwhile).
WALK = r"""([seconds, still]) => {
  clearInterval(window.__motion);
  const native = () =>
    typeof DeviceMotionEvent === "function" && DeviceMotionEvent.prototype instanceof Event;
  const start = performance.now();
  const id = setInterval(() => {
    const t = (performance.now() - start) / 1000;
    if (t > seconds) return clearInterval(id);
    const up = 2 * Math.sin(2 * Math.PI * 2 * t);
    const init = {
      acceleration: { x: 0, y: up, z: 0 },
      accelerationIncludingGravity: { x: still[0], y: still[1] + up, z: still[2] },
      interval: 16,
    };
    window.dispatchEvent(native()
      ? new DeviceMotionEvent("devicemotion", init)
      : Object.assign(new Event("devicemotion"), init));
  }, 16);
}"""


def test_show_me_in_webkit(api: httpx2.Client, pixel: Phone) -> None:
    starter = play.joined_by_link(api, pixel, play.temple(play.PAIR[0]))
    truth = play.scene(3, seed=12)
    still = still_reading([0.0, 1.0, 0.0])

    # The joiner photographs the mock camera's pattern in the app, upright and level.
    play.camera_step(pixel)
    pixel.hold_still(still)
    pixel.evaluate(ASK_MOTION, "granted")
    hold_turned(pixel, 0.0)
    play.photograph(pixel)
    expect(pixel.get_by_test_id("photo-view")).to_be_visible()
    width, height = pixel.photo_size()
    print(f"the mock camera's photo: {width:.0f} x {height:.0f}")
    k = min(width / SCENE_SIZE[0], height / SCENE_SIZE[1])
    centre, scene_centre = np.array([width, height]) / 2, np.array(SCENE_SIZE) / 2

    # The starter marks the joiner and taps three landmarks; the joiner finds them.
    found = centre + k * (np.asarray(truth.landmarks2, dtype=float) - scene_centre)
    mine = answered(starter, pixel, truth, found)
    friend = np.array(mine["friend"], dtype=float)
    focal = mine["focal_35mm"] / FILM_DIAGONAL_MM * math.hypot(width, height)
    ahead = math.degrees(math.atan((friend[0] - width / 2) / focal))
    print(f"the friend {ahead:.1f} degrees right of the photo's centre")

    # Show me, held as at the shutter.
    live, opened = show_me(pixel)
    print(f"Show me (WebKit): the first marker {opened:.0f} ms after the tap")
    _, _, video = video_on_screen(pixel, np.zeros(2))
    print(f"the mock camera's live video: {video.astype(int).tolist()}")
    # The view's quiet check of its video's focal length: the server does not match the mock
    # camera's moving pattern to the photo (one frame of it), so the assumption stays, and
    # nothing is said.
    expect(live).to_have_attribute("data-focal-check", "refused")
    note = pixel.get_by_test_id("live-note").inner_text()
    assert "did not match" not in note, note

    def marker_at(turn: float, when: str) -> float:
        """Turned right by ``turn`` degrees: the marker where the friend projects; its
        error, degrees."""
        hold_turned(pixel, turn)
        return placed_marker(pixel, friend, focal, turn, when, photo=(width, height))

    errors = [marker_at(ahead + 3.0, "at first"), marker_at(ahead - 3.0, "at first")]
    expect(pixel.get_by_test_id("live-note")).to_contain_text("inside the yellow frame")
    for away, turn in ((-90.0, "right"), (90.0, "left")):
        hold_turned(pixel, ahead + away)
        expect(pixel.get_by_test_id("live-arrow")).to_have_attribute("data-turn", turn)
        expect(pixel.get_by_test_id("live-note")).to_contain_text(f"Turn {turn}")
        expect(pixel.get_by_test_id("live-frame")).to_have_count(0)
    errors.append(marker_at(ahead + 3.0, "back from 90 degrees away"))
    # The 1 s from the tap is not for WebKitGTK's mock camera, whose first frame comes more
    # than a second after its stream (docs/browsers.md): the app's own part, from that frame
    # to the marker, is printed (101-634 ms measured) and held under the hang bound.
    steps = pixel.evaluate(OPENING_STEPS)
    after_frame = float(steps["marker-drawn"]) - float(steps["first-frame"])
    print(f"WebKit: {opened:.0f} ms from the tap, {after_frame:.0f} ms after the first frame")
    assert after_frame < OPENING_BOUND_MS, steps

    # Two minutes after the shutter by the page's clock: the view may have drifted.
    expect(live).to_have_attribute("data-warning", "none")
    drifted(pixel)
    # A walk is said (before the drift: it matters more). Twelve steps: a page the machine
    # stalls for more than 0.5 s starts the count again (trust.ts), as a paused page does,
    # and a busy suite has stalled WebKit's page that long in the six steps of 3 s.
    pixel.evaluate(WALK, [WALK_SECONDS, list(still)])
    expect(pixel.get_by_test_id("live-warning")).to_contain_text("You have moved")
    expect(live).to_have_attribute("data-warning", "moved")

    # Re-align sends a frame of the mock camera to the real server, which does not match its
    # moving pattern to the photo (one frame of it): said, and nothing moves.
    pixel.hold_still(still)
    pixel.get_by_test_id("live-align").tap()
    expect(pixel.get_by_test_id("live-note")).to_contain_text("did not match your photo")
    expect(live).to_have_attribute("data-aligning", "refused")
    expect(live).to_have_attribute("data-anchored", "true")
    expect(live).to_have_attribute("data-warning", "moved")
    assert float(live.get_attribute("data-sent-rate") or "nan") < 3.0
    errors.append(marker_at(ahead + 3.0, "after the refused Re-align"))
    print(f"marker error (WebKit), degrees: {[round(error, 3) for error in errors]}")

    pixel.get_by_test_id("live-close").tap()
    expect(live).to_have_count(0)
    expect(pixel.get_by_test_id("answer-frame")).to_be_visible()
