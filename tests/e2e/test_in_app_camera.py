"""The in-app camera, in each engine: the phone is held still at a known tilt, the person
opens the camera in the page and takes the photo; the photo goes with which way is down in
its frame (``gravity``, three times, x, y, z) and the reading's sigma, and, where the phone
has an absolute orientation (Chromium, Android), the lens's compass heading (``heading``;
WebKit sends none: iOS is left out, docs/app.md). A camera refused is
said in plain words beside the other two choices; where the phone asks for motion access
(iOS) it is asked once, and refused, the photo goes without down and the person is told. A
phone that moves at the shutter sends none: frontend/src/camera/motion.test.ts. Chromium's
fake camera and emulated sensors, WebKit's mock camera and dispatched motion events:
docs/browsers.md.
"""

from __future__ import annotations

import math

import httpx2
import numpy as np
import pytest

from testbed.browser import play
from testbed.browser.chromium_phone import ChromiumPhone
from testbed.browser.phone import Phone, expect
from testbed.browser.play import ASK_MOTION, angle_deg, quaternion, still_reading, take_photo

# The phone upright in portrait, aimed 20 degrees above the horizon and turned 6 degrees
# clockwise in the screen's plane: down in its photo (x right, y down, z into the scene).
AIM_UP, TURN = math.radians(20), math.radians(6)
DOWN = (
    math.sin(TURN) * math.cos(AIM_UP),
    math.cos(TURN) * math.cos(AIM_UP),
    -math.sin(AIM_UP),
)


READING = still_reading(DOWN)
# The same phone's lens looks this way, degrees clockwise from north (seen from above).
HEADING = 131.5


def device_to_earth(heading_deg: float) -> np.ndarray:
    """The turn (3 x 3, columns: the device's x right of the screen, y its top, z out of it,
    in the earth frame x east, y north, z up) of the phone above (AIM_UP, TURN) whose lens
    looks ``heading_deg`` from north: built from the photo's axes (x right, y down, z the
    lens), independently of camera/heading.ts."""
    h = math.radians(heading_deg)
    level = np.array([math.sin(h), math.cos(h), 0.0])  # the lens's way, seen from above
    right = np.array([math.cos(h), -math.sin(h), 0.0])
    up = np.array([0.0, 0.0, 1.0])
    lens = math.cos(AIM_UP) * level + math.sin(AIM_UP) * up
    down_upright = math.sin(AIM_UP) * level - math.cos(AIM_UP) * up
    photo_x = math.cos(TURN) * right + math.sin(TURN) * down_upright
    photo_y = math.cos(TURN) * down_upright - math.sin(TURN) * right
    turn = np.column_stack([photo_x, -photo_y, -lens])
    # The accelerometer's reading above says the same: down in the photo is DOWN.
    assert np.allclose([photo_x[2], photo_y[2], lens[2]], [-d for d in DOWN])
    return turn


# The person refuses the camera, once.
REFUSE_CAMERA_ONCE = """() => {
  const open = navigator.mediaDevices.getUserMedia.bind(navigator.mediaDevices);
  navigator.mediaDevices.getUserMedia = (constraints) => {
    navigator.mediaDevices.getUserMedia = open;
    return Promise.reject(new DOMException("Permission denied", "NotAllowedError"));
  };
}"""


@pytest.mark.engines("chromium", "webkit")
def test_the_in_app_camera_sends_down_with_the_photo(api: httpx2.Client, pixel: Phone) -> None:
    starter = play.joined_by_link(api, pixel)  # the search started over the API
    play.camera_step(pixel)
    pixel.hold_still(READING)
    if isinstance(pixel, ChromiumPhone):
        pixel.hold_orientation(quaternion(device_to_earth(HEADING)))
    if pixel.engine == "webkit":
        pixel.evaluate(ASK_MOTION, "granted")
    # Asked once, in the app's words, then the browser's; the words under the view follow
    # the phone: still, it knows down.
    form = play.photograph(pixel)
    gravity = form["gravity"]
    assert isinstance(gravity, list), form
    assert len(gravity) == 3, form
    # Within a degree of the truth (Chromium rounds its readings to 0.1 m/s^2: 0.3 degrees).
    assert angle_deg(gravity, DOWN) < 1.0, (gravity, DOWN)
    # A steady reading: the accelerometer's own bias is its sigma.
    assert form["sigma"] == 1.0, form
    # The server keeps it with the photo, for the answer (and tells the other phone), read
    # by the other phone once it is there.
    photo = pixel.wait_until(
        lambda: starter.state()["photos"]["joiner"],
        lambda found: found is not None,
        "the photo on the server",
    )
    unit = [value / math.hypot(*gravity) for value in gravity]
    assert photo["gravity"] == {"down": pytest.approx(unit, abs=1e-6), "sigma_deg": 1.0}
    if pixel.engine == "chromium":
        # The lens's heading, within 2 degrees, at the compass's sigma; kept as sent.
        heading = form["heading"]
        assert isinstance(heading, float), form
        assert abs((heading - HEADING + 180) % 360 - 180) < 2.0, (heading, HEADING)
        assert form["heading_sigma"] == 15.0, form
        assert (photo["heading"], photo["heading_sigma_deg"]) == (pytest.approx(heading), 15.0)
    else:
        # WebKit, as iOS: no absolute orientation, no heading.
        assert (form["heading"], photo["heading"]) == (None, None), (form, photo)
    # The camera is closed: the photo is on screen, tappable.
    expect(pixel.get_by_test_id("in-app-camera")).to_have_count(0)


def test_refused_camera_and_motion_access(api: httpx2.Client, iphone: Phone) -> None:
    play.joined_by_link(api, iphone)
    play.camera_step(iphone)
    iphone.hold_still(READING)
    iphone.evaluate(ASK_MOTION, "denied")
    iphone.evaluate(REFUSE_CAMERA_ONCE)
    iphone.get_by_test_id("open-camera").tap()
    iphone.get_by_test_id("motion-allow").tap()
    # The camera refused: said in plain words, the phone's camera app and the gallery there.
    expect(iphone.get_by_test_id("camera-problem")).to_contain_text("camera was not allowed")
    expect(iphone.locator('label[for="photo-input"]')).to_be_visible()
    expect(iphone.locator('label[for="photo-pick"]')).to_be_visible()
    # Again: the motion question is not asked twice; its refusal is told, and the photo goes
    # without down.
    iphone.get_by_test_id("open-camera").tap()
    expect(iphone.get_by_test_id("camera-note")).to_contain_text("Motion access is off")
    expect(iphone.get_by_test_id("motion-question")).to_have_count(0)
    form = take_photo(iphone)
    assert form["gravity"] == [], form
    assert form["sigma"] is None, form
