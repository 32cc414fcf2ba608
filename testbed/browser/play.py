"""Plays a search in the app, as the end-to-end tests' two friends do: start and join, upload
the temple photos, mark the friend or say they cannot be seen, tap and find landmarks; then
reads what a phone shows and what the server keeps (the state, the answer, the photo).

The temple photos stand in for the venue (``scene``: landmarks projected from 3-D points with
the calibrated cameras). Tests use it as a module: ``play.start_and_join(...)``.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any

import httpx2
import numpy as np

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
    digits = re.sub(r"\D", "", code.inner_text())
    joiner.goto(
        f"{joiner_server or server}/join/{digits}"
    )  # the join link, opened on the friend's phone
    expect(starter.get_by_test_id("waiting")).to_be_hidden()
    if audit:
        focused(joiner, "photo-step-title")  # a new screen: its title is read first
        joiner.audit("the photo step")
    if photos:
        upload(starter, temple(PAIR[0]))
        upload(joiner, temple(PAIR[1]))
    return starter, joiner


def focused(page: Phone, test_id: str) -> None:
    """Focus is on the element of ``test_id`` (the app moves it to the next step)."""
    active = "() => document.activeElement && document.activeElement.outerHTML.slice(0, 80)"
    seen: list[str] = []

    def there() -> bool:
        seen[:] = [page.evaluate(active)]
        return f'data-testid="{test_id}"' in seen[0]

    try:
        page.wait_for(there, f"focus on {test_id}")
    except AssertionError as failed:
        raise AssertionError(f"{failed}; it is on {seen[-1:]}") from None


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


def to_the_curve(server: str, starter: Phone, joiner: Phone) -> Phone:
    """A search whose taps fit no two phone photos, played to its curve: the starter marks
    the friend and 5 landmarks, the joiner finds 4 of them and sees the curve; the joiner."""
    start_and_join(server, starter, joiner, photos=True)
    mark_friend(starter, *NO_PHONES_FRIEND)
    tap_landmarks(starter, NO_PHONES_LANDMARKS1)
    cannot_see(joiner)
    find_landmarks(joiner, NO_PHONES_LANDMARKS2[:4])
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
    x0, y0, x1, y1 = (
        float(frame.get_attribute(f"data-{n}") or "nan") for n in ("x0", "y0", "x1", "y1")
    )
    return x0, y0, x1, y1


def reported_position(page: Phone) -> tuple[np.ndarray, tuple[float, float, float], str]:
    """Where the phone says its friend is, the 95 % ellipse and how it knows."""
    position = page.get_by_test_id("result-position")
    expect(position).to_be_visible()
    x, y, a, b, angle = (
        float(position.get_attribute(f"data-{name}") or "nan")
        for name in ("x", "y", "axis-a", "axis-b", "angle")
    )
    return np.array([x, y]), (a, b, angle), position.get_attribute("data-how") or ""


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


def stored_photo(server: str, page: Phone, role: str) -> bytes:
    """The photo of ``role`` as the server keeps it (the JPEG), read with this phone's
    session once it is there."""
    joined = page.evaluate("() => JSON.parse(localStorage.getItem('buddy-search.session'))")
    url = f"{server}/api/sessions/{joined['session_id']}/photo/{role}"
    auth = {"Authorization": f"Bearer {joined['token']}"}
    stored: list[httpx2.Response] = []

    def landed() -> bool:
        stored[:] = [httpx2.get(url, headers=auth)]
        return stored[0].is_success

    page.wait_for(landed, f"the {role}'s photo on the server")
    return stored[0].content


def view_scale(page: Phone) -> float:
    return float(page.get_by_test_id("photo-view").get_attribute("data-scale") or "nan")


def tap_sigma(scale: float, engine: str) -> float:
    """A tap's precision at ``scale`` CSS px per photo px (docs/app.md): a finger's in
    Chromium (touch), a pointer's in WebKit (its driver has no touch: the mouse, aimed)."""
    spread = TAP_PRECISION["finger_css" if engine == "chromium" else "loupe_css"]
    return max(TAP_PRECISION["min_sigma_px"], spread / scale)
