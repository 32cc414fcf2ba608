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
from collections.abc import Sequence

import cv2
import httpx2
import numpy as np
import pytest

from testbed.browser.chromium_phone import ChromiumPhone
from testbed.browser.phone import Phone, expect
from testbed.client import Phone as ApiPhone
from testbed.client import start

GRAVITY = 9.80665
# The phone upright in portrait, aimed 20 degrees above the horizon and turned 6 degrees
# clockwise in the screen's plane: down in its photo (x right, y down, z into the scene).
AIM_UP, TURN = math.radians(20), math.radians(6)
DOWN = (
    math.sin(TURN) * math.cos(AIM_UP),
    math.cos(TURN) * math.cos(AIM_UP),
    -math.sin(AIM_UP),
)


def still_reading(down: Sequence[float]) -> tuple[float, float, float]:
    """What the accelerometer of a phone held still in portrait reads (m/s^2, device frame:
    x right, y up the screen, z out of the screen; the push against gravity) when ``down``
    (a unit 3-vector) is down in its upright photo's camera frame (x right, y down, z into
    the scene): camera/gravity.ts's map from reading to photo at screen angle 0, inverted."""
    return (-GRAVITY * down[0], GRAVITY * down[1], GRAVITY * down[2])


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


def quaternion(turn: np.ndarray) -> tuple[float, float, float, float]:
    """The unit quaternion (x, y, z, w) of a 3 x 3 turn: its axis times sin(angle / 2), and
    cos(angle / 2) (OpenCV's Rodrigues vector is the axis times the angle)."""
    vector = cv2.Rodrigues(turn)[0].ravel()
    angle = float(np.linalg.norm(vector))
    x, y, z = vector / angle * math.sin(angle / 2) if angle > 0 else (0.0, 0.0, 0.0)
    return float(x), float(y), float(z), math.cos(angle / 2)


# Before the camera opens: keep the form fields of every photo the page sends.
SPY = """() => {
  window.sent = [];
  const send = XMLHttpRequest.prototype.send;
  XMLHttpRequest.prototype.send = function (body) {
    if (body instanceof FormData && body.has("photo")) {
      window.sent.push({
        gravity: body.getAll("gravity").map(Number),
        sigma: body.has("gravity_sigma_deg") ? Number(body.get("gravity_sigma_deg")) : null,
        heading: body.has("heading") ? Number(body.get("heading")) : null,
        heading_sigma: body.has("heading_sigma_deg") ? Number(body.get("heading_sigma_deg")) : null,
        type: body.get("photo").type,
      });
    }
    return send.call(this, body);
  };
}"""

# iOS asks for motion access (the system's prompt); the person's answer is the argument.
# Chromium asks through the same DeviceMotionEvent.requestPermission (granted in the tests);
# WebKitGTK has none, nor a DeviceMotionEvent: the test gives it iOS's.
ASK_MOTION = """(answer) => {
  window.DeviceMotionEvent = window.DeviceMotionEvent || function () {};
  DeviceMotionEvent.requestPermission = () => Promise.resolve(answer);
}"""


# The person refuses the camera, once.
REFUSE_CAMERA_ONCE = """() => {
  const open = navigator.mediaDevices.getUserMedia.bind(navigator.mediaDevices);
  navigator.mediaDevices.getUserMedia = (constraints) => {
    navigator.mediaDevices.getUserMedia = open;
    return Promise.reject(new DOMException("Permission denied", "NotAllowedError"));
  };
}"""


def joined(server: str, api: httpx2.Client, phone: Phone) -> ApiPhone:
    """A search started over the API, joined by ``phone`` with its link: the photo step.
    Returns the starter's calls."""
    starter, code = start(api)
    phone.goto(f"{server}/join/{code}")
    expect(phone.get_by_test_id("open-camera")).to_be_visible()
    phone.evaluate(SPY)
    return starter


def kept(starter: ApiPhone, phone: Phone) -> dict[str, object] | None:
    """The joiner's photo as the server keeps it, read by the other phone once it is there."""
    found: list[dict[str, object] | None] = []

    def stored() -> bool:
        found[:] = [starter.state()["photos"]["joiner"]]
        return found[0] is not None

    phone.wait_for(stored, "the photo on the server")
    return found[0]


def take_photo(phone: Phone) -> dict[str, object]:
    """Open the in-app camera, wait for the live view, take the photo: the form sent."""
    camera = phone.get_by_test_id("in-app-camera")
    expect(camera).to_have_attribute("data-phase", "live")
    phone.get_by_test_id("shutter").tap()
    expect(phone.get_by_test_id("photo-view")).to_be_visible()
    sent: list[dict[str, object]] = []

    def photo_sent() -> bool:
        sent[:] = phone.evaluate("() => window.sent")
        return len(sent) > 0

    phone.wait_for(photo_sent, "the photo's upload")
    assert len(sent) == 1, sent
    return sent[0]


def angle_deg(a: list[float], b: tuple[float, float, float]) -> float:
    cos = sum(x * y for x, y in zip(a, b, strict=True)) / math.hypot(*a) / math.hypot(*b)
    return math.degrees(math.acos(min(1.0, cos)))


@pytest.mark.engines("chromium", "webkit")
def test_the_in_app_camera_sends_down_with_the_photo(
    server: str, api: httpx2.Client, pixel: Phone
) -> None:
    starter = joined(server, api, pixel)
    pixel.hold_still(READING)
    if isinstance(pixel, ChromiumPhone):
        pixel.hold_orientation(quaternion(device_to_earth(HEADING)))
    if pixel.engine == "webkit":
        pixel.evaluate(ASK_MOTION, "granted")
    pixel.get_by_test_id("open-camera").tap()
    # Asked once, in the app's words, then the browser's.
    expect(pixel.get_by_test_id("motion-question")).to_contain_text("which way is down")
    pixel.get_by_test_id("motion-allow").tap()
    # The words under the view follow the phone: still, it knows down.
    expect(pixel.get_by_test_id("camera-note")).to_contain_text("Which way is down is known")
    form = take_photo(pixel)
    gravity = form["gravity"]
    assert isinstance(gravity, list), form
    assert len(gravity) == 3, form
    # Within a degree of the truth (Chromium rounds its readings to 0.1 m/s^2: 0.3 degrees).
    assert angle_deg(gravity, DOWN) < 1.0, (gravity, DOWN)
    # A steady reading: the accelerometer's own bias is its sigma.
    assert form["sigma"] == 1.0, form
    # The server keeps it with the photo, for the answer (and tells the other phone).
    photo = kept(starter, pixel)
    assert photo is not None
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


def test_refused_camera_and_motion_access(server: str, api: httpx2.Client, iphone: Phone) -> None:
    joined(server, api, iphone)
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
