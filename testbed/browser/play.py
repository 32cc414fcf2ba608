"""Plays a search in the app, as the end-to-end tests' two friends do: start and join, upload
the temple photos, mark the friend or say they cannot be seen, tap and find landmarks; then
reads what a phone shows and what the server keeps (the state, the answer, the photo).

The temple photos stand in for the venue (``scene``: landmarks projected from 3-D points with
the calibrated cameras). Tests use it as a module: ``play.start_and_join(...)``. The in-app
camera's steps are here too (``photograph``: a phone held still, its photo taken in the app),
with what they send (``SPY``) and the readings of a still phone (``still_reading``).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import cv2
import httpx2
import numpy as np

from testbed.client import Phone as ApiPhone
from testbed.client import start
from testbed.scenes import (
    NO_PHONES_FRIEND,
    NO_PHONES_LANDMARKS1,
    NO_PHONES_LANDMARKS2,
    Scene,
    temple_scene,
)

from .phone import Phone, expect

ROOT = Path(__file__).parents[2]
TEMPLE = ROOT / "tests" / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")
TAP_PRECISION = json.loads((ROOT / "backend" / "limits.json").read_text())["tap_precision"]


def scene(landmarks: int, seed: int) -> Scene:
    return temple_scene(TEMPLE / "templeSR_par.txt", *PAIR, landmarks, np.random.default_rng(seed))


def temple(name: str) -> Path:
    return TEMPLE / f"{name}.png"


def start_and_join(
    server: str,
    starter: Phone,
    joiner: Phone,
    *,
    screenshots: Path | None = None,
    joiner_server: str | None = None,
    photos: bool = False,
    audit: bool = False,
) -> tuple[Phone, Phone]:
    """One friend starts a search; the other opens its join link (at ``joiner_server`` when
    its network goes another way); with ``photos``, each then uploads its temple photo."""
    digits = started(server, starter, screenshots=screenshots, audit=audit)
    joiner.goto(f"{joiner_server or server}/join/{digits}")  # the join link, on the friend's phone
    expect(starter.get_by_test_id("waiting")).to_be_hidden()
    if audit:
        focused(joiner, "photo-step-title")  # a new screen: its title is read first
        joiner.audit("the photo step")
    if photos:
        upload(starter, temple(PAIR[0]))
        upload(joiner, temple(PAIR[1]))
    return starter, joiner


def started(
    server: str, starter: Phone, *, screenshots: Path | None = None, audit: bool = False
) -> str:
    """The starter's phone starts a search and shares it (its code, a QR code, waiting for
    the friend): the code's digits."""
    starter.goto(f"{server}/")
    if screenshots:
        starter.screenshot(path=screenshots / "1-start.png")
    expect(starter.get_by_test_id("start")).to_have_text("Start a search")
    if audit:
        starter.audit("the start")
    starter.get_by_test_id("start").tap()
    code = starter.get_by_test_id("code")
    expect(code).to_have_text(re.compile(r"^\s*\d{4}\s?\d{4}\s*$"))
    expect(starter.get_by_test_id("qr")).to_be_visible()
    expect(starter.get_by_test_id("waiting")).to_be_visible()
    if screenshots:
        starter.screenshot(path=screenshots / "2-share.png")
    if audit:
        starter.audit("sharing the code")
    return re.sub(r"\D", "", code.inner_text())


def joined_by_link(api: httpx2.Client, phone: Phone, photo: Path | None = None) -> ApiPhone:
    """A search started over the API (with the starter's ``photo`` when given), joined by
    ``phone`` with the app's link: the starter's calls."""
    starter, code = start(api, photo)
    phone.goto(str(api.base_url.join(f"/join/{code}")))
    return starter


def focused(page: Phone, test_id: str) -> None:
    """Focus is on the element of ``test_id`` (the app moves it to the next step)."""
    active = "() => document.activeElement && document.activeElement.outerHTML.slice(0, 80)"
    page.wait_until(
        lambda: str(page.evaluate(active)),
        lambda seen: f'data-testid="{test_id}"' in seen,
        f"focus on {test_id}",
    )


def upload(page: Phone, photo: Path, size: tuple[int, int] = (640, 480)) -> None:
    """``photo`` from the gallery, shown at its ``size`` (width, height; a temple photo's)."""
    page.get_by_test_id("photo-input").set_input_files(photo)
    view = page.get_by_test_id("photo-view")
    expect(view).to_have_attribute("data-photo-width", str(size[0]))
    expect(view).to_have_attribute("data-photo-height", str(size[1]))


def mark_friend(page: Phone, x: float, y: float) -> None:
    """'Tap your friend': a tap on them."""
    expect(page.get_by_test_id("friend-prompt")).to_contain_text("Tap your friend")
    page.tap_photo(x, y)
    expect(page.get_by_test_id("friend-mark")).to_be_visible()


def cannot_see(page: Phone) -> None:
    """'I can't see them': landmarks only on this phone."""
    page.get_by_test_id("cannot-see").tap()
    expect(page.get_by_test_id("friend-prompt")).to_have_count(0)


def tap_landmark(page: Phone, number: int, point: np.ndarray) -> None:
    """A tap on photo pixel ``point`` that places landmark #``number``."""
    page.tap_photo(*map(float, point))
    expect(page.locator(f'[data-testid="landmark"][data-id="{number}"]')).to_be_visible()


def tap_landmarks(page: Phone, points: np.ndarray, first_id: int = 1, online: bool = True) -> None:
    """New landmarks, numbered from ``first_id``: saved, or (not ``online``) not saved."""
    for number, point in enumerate(points, start=first_id):
        tap_landmark(page, number, point)
    if online:
        saved(page)
    else:
        expect(page.get_by_test_id("save-state")).not_to_have_attribute("data-state", "saved")


def find_landmarks(page: Phone, points: np.ndarray, first_id: int = 1, online: bool = True) -> None:
    """The landmarks the other phone numbered, each found with its crop as the prompt
    (neither crop nor save checked when the phone is not ``online``)."""
    for number, point in enumerate(points, start=first_id):
        prompt = page.get_by_test_id("find-prompt")
        expect(prompt).to_have_attribute("data-id", str(number))
        if online:
            expect(prompt.locator("img")).to_be_visible()
        tap_landmark(page, number, point)
    if online:
        saved(page)


def marked_and_found(
    starter: Phone,
    joiner: Phone,
    friend: Sequence[float] | np.ndarray,
    landmarks1: np.ndarray,
    landmarks2: np.ndarray,
) -> None:
    """The search most tests play: the starter marks its ``friend`` and taps ``landmarks1``;
    the joiner, who cannot see its friend, finds them at ``landmarks2`` (as many as given)."""
    mark_friend(starter, *friend)
    tap_landmarks(starter, landmarks1)
    cannot_see(joiner)
    find_landmarks(joiner, landmarks2)


def to_the_curve(server: str, starter: Phone, joiner: Phone) -> Phone:
    """A search whose taps fit no two phone photos, played to its curve: the starter marks
    the friend and 5 landmarks, the joiner finds 4 of them and sees the curve; the joiner."""
    start_and_join(server, starter, joiner, photos=True)
    marked_and_found(
        starter, joiner, NO_PHONES_FRIEND, NO_PHONES_LANDMARKS1, NO_PHONES_LANDMARKS2[:4]
    )
    expect(joiner.get_by_test_id("answer-curve")).to_be_visible()
    return joiner


def saved(page: Phone) -> None:
    expect(page.get_by_test_id("save-state")).to_have_attribute("data-state", "saved")


def needed(page: Phone, count: int) -> None:
    """The state's count of landmarks both photos still need (never shown as such)."""
    expect(page.get_by_test_id("next-step")).to_have_attribute("data-needed", str(count))


def framed(page: Phone) -> tuple[float, float, float, float]:
    """The answer's frame as drawn on the phone: (x0, y0, x1, y1), photo px; once the view
    has settled (it may wait for the fingers' quiet, then glide, to bring it into view)."""
    frame = page.get_by_test_id("answer-frame")
    expect(frame).to_be_visible()
    page.view_box()
    x0, y0, x1, y1 = frame.numbers("x0", "y0", "x1", "y1")
    return x0, y0, x1, y1


def reported_position(page: Phone) -> tuple[np.ndarray, tuple[float, float, float], str]:
    """Where the phone says its friend is, the 95 % ellipse and how it knows."""
    position = page.get_by_test_id("result-position")
    expect(position).to_be_visible()
    x, y, a, b, angle = position.numbers("x", "y", "axis-a", "axis-b", "angle")
    return np.array([x, y]), (a, b, angle), position.get_attribute("data-how") or ""


def found_at(
    page: Phone, truth: np.ndarray, how: str = "solved"
) -> tuple[np.ndarray, tuple[float, float, float]]:
    """The phone's answer, known as ``how`` says, its 95 % ellipse holding ``truth`` (an
    honest region, the claim every answer makes): its centre and ellipse."""
    centre, ellipse, said = reported_position(page)
    assert said == how, said
    assert inside(truth, centre, ellipse), (centre, ellipse, truth)
    return centre, ellipse


def inside(truth: np.ndarray, centre: np.ndarray, ellipse: tuple[float, float, float]) -> bool:
    a, b, angle = ellipse
    dx, dy = truth - centre
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    along, across = c * dx + s * dy, -s * dx + c * dy
    return (along / a) ** 2 + (across / b) ** 2 <= 1.0


def session_state(page: Phone) -> dict[str, Any]:
    """The session as the server tells this phone (GET /api/sessions/{id}, its own token)."""
    state: dict[str, Any] = page.evaluate(
        """async () => {
            const { session_id, token } = JSON.parse(localStorage.getItem("buddy-search.session"));
            const headers = { Authorization: `Bearer ${token}` };
            return (await fetch(`/api/sessions/${session_id}`, { headers })).json();
        }"""
    )
    return state


def answer_in(page: Phone, role: str) -> dict[str, Any]:
    """The answer's part for ``role``'s photo, as the server tells this phone."""
    mine: dict[str, Any] = session_state(page)["answer"]["in_photo"][role]
    return mine


def stored_photo(server: str, page: Phone, role: str) -> bytes:
    """The photo of ``role`` as the server keeps it (the JPEG), read with this phone's
    session once it is there."""
    joined = page.evaluate("() => JSON.parse(localStorage.getItem('buddy-search.session'))")
    url = f"{server}/api/sessions/{joined['session_id']}/photo/{role}"
    auth = {"Authorization": f"Bearer {joined['token']}"}
    stored = page.wait_until(
        lambda: httpx2.get(url, headers=auth),
        lambda response: response.is_success,
        f"the {role}'s photo on the server",
    )
    return stored.content


def view_scale(page: Phone) -> float:
    (scale,) = page.get_by_test_id("photo-view").numbers("scale")
    return scale


def tap_sigma(scale: float, engine: str) -> float:
    """A tap's precision at ``scale`` CSS px per photo px (docs/app.md): a finger's in
    Chromium (touch), a pointer's in WebKit (its driver has no touch: the mouse, aimed)."""
    spread = TAP_PRECISION["finger_css" if engine == "chromium" else "loupe_css"]
    return max(TAP_PRECISION["min_sigma_px"], spread / scale)


# --- the in-app camera -------------------------------------------------------------------

GRAVITY = 9.80665

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


def still_reading(down: Sequence[float]) -> tuple[float, float, float]:
    """What the accelerometer of a phone held still in portrait reads (m/s^2, device frame:
    x right, y up the screen, z out of the screen; the push against gravity) when ``down``
    (a unit 3-vector) is down in its upright photo's camera frame (x right, y down, z into
    the scene): camera/gravity.ts's map from reading to photo at screen angle 0, inverted."""
    return (-GRAVITY * down[0], GRAVITY * down[1], GRAVITY * down[2])


def quaternion(turn: np.ndarray) -> tuple[float, float, float, float]:
    """The unit quaternion (x, y, z, w) of a 3 x 3 turn: its axis times sin(angle / 2), and
    cos(angle / 2) (OpenCV's Rodrigues vector is the axis times the angle)."""
    vector = cv2.Rodrigues(turn)[0].ravel()
    angle = float(np.linalg.norm(vector))
    x, y, z = vector / angle * math.sin(angle / 2) if angle > 0 else (0.0, 0.0, 0.0)
    return float(x), float(y), float(z), math.cos(angle / 2)


def angle_deg(a: list[float], b: tuple[float, float, float]) -> float:
    cos = sum(x * y for x, y in zip(a, b, strict=True)) / math.hypot(*a) / math.hypot(*b)
    return math.degrees(math.acos(min(1.0, cos)))


def camera_step(phone: Phone) -> None:
    """The photo step, its in-app camera offered; what the page sends from now on is kept
    (``SPY``, read by :func:`take_photo`)."""
    expect(phone.get_by_test_id("open-camera")).to_be_visible()
    phone.evaluate(SPY)


def take_photo(phone: Phone) -> dict[str, object]:
    """Open the in-app camera, wait for the live view, take the photo: the form sent."""
    camera = phone.get_by_test_id("in-app-camera")
    expect(camera).to_have_attribute("data-phase", "live")
    phone.get_by_test_id("shutter").tap()
    expect(phone.get_by_test_id("photo-view")).to_be_visible()
    sent: list[dict[str, object]] = phone.wait_until(
        lambda: phone.evaluate("() => window.sent"),
        lambda sent: len(sent) > 0,
        "the photo's upload",
    )
    assert len(sent) == 1, sent
    return sent[0]


def photograph(phone: Phone, audit: bool = False) -> dict[str, object]:
    """The in-app camera opened on a phone held still (its sensors set first), motion
    access asked once, in the app's words, and allowed; once the words under the view say
    down is known, the photo taken (with ``audit``, the camera's screen audited first). The
    form sent."""
    phone.get_by_test_id("open-camera").tap()
    expect(phone.get_by_test_id("motion-question")).to_contain_text("which way is down")
    phone.get_by_test_id("motion-allow").tap()
    expect(phone.get_by_test_id("camera-note")).to_contain_text("Which way is down is known")
    if audit:
        phone.audit("the in-app camera")
    return take_photo(phone)
