"""The in-app camera, in each engine: the phone is held still at a known tilt, the person
opens the camera in the page and takes the photo; the photo goes with which way is down in
its frame (``gravity``, three times, x, y, z) and the reading's sigma. A camera refused is
said in plain words beside the other two choices; where the phone asks for motion access
(iOS) it is asked once, and refused, the photo goes without down and the person is told. A
phone that moves at the shutter sends none: frontend/src/camera/motion.test.ts. Chromium's
fake camera and emulated sensors, WebKit's mock camera and dispatched motion events:
docs/browsers.md.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import httpx2
import pytest
from phone import Phone, expect

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

# Before the camera opens: keep the form fields of every photo the page sends.
SPY = """() => {
  window.sent = [];
  const send = XMLHttpRequest.prototype.send;
  XMLHttpRequest.prototype.send = function (body) {
    if (body instanceof FormData && body.has("photo")) {
      window.sent.push({
        gravity: body.getAll("gravity").map(Number),
        sigma: body.has("gravity_sigma_deg") ? Number(body.get("gravity_sigma_deg")) : null,
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


def joined(server: str, phone: Phone) -> dict[str, str]:
    """A search started over the API, joined by ``phone`` with its link: the photo step.
    Returns the starter's session (``session_id``, ``token``)."""
    created = httpx2.post(f"{server}/api/sessions").raise_for_status().json()
    phone.goto(f"{server}/join/{created['join_code']}")
    expect(phone.get_by_test_id("open-camera")).to_be_visible()
    phone.evaluate(SPY)
    return {"session_id": created["session_id"], "token": created["token"]}


def kept(server: str, starter: dict[str, str], phone: Phone) -> dict[str, object] | None:
    """The joiner's photo as the server keeps it, read by the other phone once it is there."""
    url = f"{server}/api/sessions/{starter['session_id']}"
    headers = {"Authorization": f"Bearer {starter['token']}"}
    found: list[dict[str, object] | None] = []

    def stored() -> bool:
        found[:] = [httpx2.get(url, headers=headers).raise_for_status().json()["photos"]["joiner"]]
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
def test_the_in_app_camera_sends_down_with_the_photo(server: str, pixel: Phone) -> None:
    starter = joined(server, pixel)
    pixel.hold_still(READING)
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
    photo = kept(server, starter, pixel)
    assert photo is not None
    unit = [value / math.hypot(*gravity) for value in gravity]
    assert photo["gravity"] == {"down": pytest.approx(unit, abs=1e-6), "sigma_deg": 1.0}
    # The camera is closed: the photo is on screen, tappable.
    expect(pixel.get_by_test_id("in-app-camera")).to_have_count(0)


def test_refused_camera_and_motion_access(server: str, iphone: Phone) -> None:
    joined(server, iphone)
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
