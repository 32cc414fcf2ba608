"""Do the phone app's taps carry honest precisions? Held out, through the app.

Two phones (Pixel 7 and iPhone 13, emulated in Chromium with touch) on a live server play
``--trials`` searches: photo 1's phone taps its friend and 5 landmarks, photo 2's phone
says it cannot see its friend and finds the same 5, every tap a quick finger tap on the
whole photo (the app's default zoom, no pinch), zoomed in first only where a button over
the photo ("Show me", "Re-check") lies on the spot. The scenes are phone scenes
(:func:`testbed.phones.phone_scene`: 12 MP photos, stored at 2560 px, 20-80 m apart), and
the taps land where the scene puts each spot, plus a finger's miss: per tap a standard
deviation drawn uniformly from 1 to 2 CSS px, per axis ("a finger is off by one or two CSS
pixels"), a model of fingers the app does not share. The app sends each tap's precision
(docs/app.md); the server answers; the benchmark reads the answer's 95 % region for photo 2
and asks whether it holds where the friend really is.

Against its peer in the same run, on the same taps: the server's old rule, one fixed 3 px
for every tap (``solve`` with ``tap_sigma=3`` and no per-tap precision).

    .venv/bin/python benchmarks/taps.py [--trials N] [--out PATH]     (``make bench-taps``)

The report is printed and written as Markdown to ``docs/tap-precision.md``.
"""

from __future__ import annotations

import io
import json
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import httpx2
import numpy as np
from PIL import Image
from playwright.sync_api import sync_playwright
from report import ROOT, command_line, markdown_table, publish, source_state

from deploy.replica import serve
from shared_solver import SolverError, solve
from shared_solver.estimation.uncertainty import contains
from testbed import chromium
from testbed.browser.chromium_phone import ChromiumPhone
from testbed.browser.phone import expect
from testbed.browser.play import inside
from testbed.client import Phone, pair
from testbed.phones import PhoneScene, phone_scene

DEFAULT_OUT = ROOT / "docs" / "tap-precision.md"
SEED = 20261125
LANDMARKS = 5
STORED_SIDE = 2560
FINGER_CSS = (1.0, 2.0)  # a finger's miss: sd per axis, CSS px, uniform between these
OLD_TAP_SIGMA = 3.0
# Spots a person would tap on the whole photo are apart on the screen: no two of a photo's
# taps closer than this fraction of its diagonal (about 50 CSS px on a phone: closer, a tap
# may land on another landmark's number, which selects that landmark instead).
APART = 0.1
LEVEL = 0.95


@dataclass(frozen=True)
class Trial:
    """One search: whether each rule's region held the truth, and the taps' sigmas."""

    error_px: float
    held: bool | None  # None: no region claimed
    held_fixed: bool | None
    sigmas: list[float]
    axis_px: float | None
    zoomed: int = 0  # taps zoomed in first (a button lay over the spot)


def stored(scene: PhoneScene, which: int) -> tuple[float, tuple[int, int]]:
    """The stored photo's scale and size for photo ``which``."""
    width, height = scene.image_size1 if which == 1 else scene.image_size2
    scale = STORED_SIDE / max(width, height)
    return scale, (round(width * scale), round(height * scale))


def blank_photo(size: tuple[int, int]) -> bytes:
    """A plain JPEG of the stored size: what is tapped is where the scene says, not what
    the photo shows."""
    buffer = io.BytesIO()
    Image.new("RGB", size, (96, 104, 112)).save(buffer, "JPEG", quality=80)
    return buffer.getvalue()


def finger(phone: ChromiumPhone, x: float, y: float, rng: np.random.Generator) -> bool:
    """A quick tap aimed at photo pixel (x, y), missing as a finger does: on the whole
    photo, or zoomed in where a control lies over the spot (then True)."""
    sigma = rng.uniform(*FINGER_CSS)
    phone.whole_photo()
    sx, sy, zoomed = reachable(phone, x, y)
    phone.tap_at(sx + rng.normal(0.0, sigma), sy + rng.normal(0.0, sigma))
    return zoomed


# Whether a tap near a client point reaches the photo wherever the finger lands: within
# ``r`` px of it (a finger's miss, three of its sigmas), no button over the photo ("Show me",
# "Re-check #n" in the status, which lets taps through elsewhere).
REACHES_PHOTO = """([x, y, r]) => [[0, 0], [-r, 0], [r, 0], [0, -r], [0, r], [-r, -r], [r, -r],
  [-r, r], [r, r]].every(([dx, dy]) =>
  Boolean(document.elementFromPoint(x + dx, y + dy)?.closest('[data-testid=photo-view]')))"""
ZOOMS = 8  # wheel steps at most, each 1.8x
WHEEL_PX = -300.0


def reachable(phone: ChromiumPhone, x: float, y: float) -> tuple[float, float, bool]:
    """Client coordinates of photo pixel (x, y) where a tap reaches the photo, and whether
    the view was zoomed for it. A spot under a button over the photo's top is brought down
    as a person would bring it out: zoomed in (the wheel, 1.8x a step) about the photo
    view's top edge above the spot."""
    page = phone.page
    for step in range(ZOOMS):
        # As the view is now: waiting for an answer's glide would undo the zoom.
        sx, sy = phone.photo_to_screen(x, y, settled=False)
        if phone.evaluate(REACHES_PHOTO, [sx, sy, 3 * FINGER_CSS[1]]):
            return sx, sy, step > 0
        page.mouse.move(sx, phone.view_box(settled=False)[1] + 1.0)
        page.mouse.wheel(0.0, WHEEL_PX)
    raise AssertionError(f"photo pixel ({x:.0f}, {y:.0f}) stays under a control")


def open_session(phone: ChromiumPhone, server: str, caller: Phone, size: tuple[int, int]) -> None:
    """``caller``'s session on ``phone``'s screen, its credentials stored as the app keeps them."""
    credentials = {"session_id": caller.session_id, "token": caller.token, "role": caller.role}
    phone.goto(f"{server}/")
    phone.evaluate(
        "(c) => localStorage.setItem('buddy-search.session', JSON.stringify(c))", credentials
    )
    phone.goto(f"{server}/s")  # the session's screen, as after a reload
    expect(phone.get_by_test_id("photo-view")).to_have_attribute("data-photo-width", str(size[0]))
    phone.whole_photo()


def play(
    server: str,
    phones: Sequence[ChromiumPhone],
    scene: PhoneScene,
    rng: np.random.Generator,
) -> Trial:
    """One search through the app; the region photo 2's phone is shown, judged."""
    http = httpx2.Client(base_url=server, timeout=30)
    starter, joiner = pair(http)
    scale1, size1 = stored(scene, 1)
    scale2, size2 = stored(scene, 2)
    for phone, size in ((starter, size1), (joiner, size2)):
        phone.uploaded(blank_photo(size))
    one, two = phones
    open_session(one, server, starter, size1)
    open_session(two, server, joiner, size2)

    expect(one.get_by_test_id("friend-prompt")).to_be_visible()
    x, y = scale1 * scene.epipole1
    zoomed = int(finger(one, x, y, rng))
    expect(one.get_by_test_id("friend-mark")).to_be_visible()
    for number, (x, y) in enumerate(scale1 * scene.landmarks1[:LANDMARKS], 1):
        zoomed += finger(one, x, y, rng)
        placed(one, number)
    two.get_by_test_id("cannot-see").tap()
    for number, (x, y) in enumerate(scale2 * scene.landmarks2[:LANDMARKS], 1):
        expect(two.get_by_test_id("find-prompt")).to_have_attribute("data-id", str(number))
        zoomed += finger(two, x, y, rng)
        placed(two, number)
    state = joiner.state()
    starter.call("DELETE")
    http.close()
    return replace(judge(state, scale2 * scene.epipole2, size1, size2), zoomed=zoomed)


def placed(phone: ChromiumPhone, number: int) -> None:
    """Landmark ``number`` marked and saved: the answer it gives is on the screen before
    the next tap is aimed (a person looks before tapping again; a status that came up as
    the finger fell would catch the tap, and no mark would come of it)."""
    expect(phone.locator(f'[data-testid="landmark"][data-id="{number}"]')).to_be_visible()
    expect(phone.get_by_test_id("save-state")).to_have_attribute("data-state", "saved")


def judge(
    state: dict[str, Any],
    truth: np.ndarray,
    size1: tuple[int, int],
    size2: tuple[int, int],
) -> Trial:
    """Whether the answer's region, and the old rule's on the same taps, hold ``truth``."""
    answer = state["answer"]
    mine = answer["in_photo"]["joiner"]
    taps1, taps2 = state["taps"]["starter"], state["taps"]["joiner"]
    sigmas = [t["sigma"] for t in taps1["landmarks"] + taps2["landmarks"]]
    sigmas.append(taps1["friend"]["sigma"])
    region = mine["region"]
    held = None
    if region is not None:
        ellipse = (*region["axes"], region["angle_deg"])
        held = bool(inside(truth, np.array(region["center"]), ellipse))  # json counts bool
    points1 = [(t["x"], t["y"]) for t in taps1["landmarks"]]
    points2 = [(t["x"], t["y"]) for t in taps2["landmarks"]]
    friend = (taps1["friend"]["x"], taps1["friend"]["y"])
    held_fixed = None
    try:
        fixed = solve(
            points1,
            points2,
            epipole1=friend,
            tap_sigma=OLD_TAP_SIGMA,
            image_size1=size1,
            image_size2=size2,
            camera1="phone",
            camera2="phone",
        )
        if fixed.epipole2 is not None and fixed.uncertainty and fixed.uncertainty.covariance:
            held_fixed = bool(
                contains(np.array(fixed.epipole2), np.array(fixed.uncertainty.covariance), truth)
            )
    except SolverError:
        pass
    position = mine["friend"]
    error = float(np.hypot(*(np.array(position) - truth))) if position else float("inf")
    axis = None if region is None else float(max(region["axes"]))
    return Trial(error, held, held_fixed, sigmas, axis)


def run(trials: int) -> list[Trial]:
    results: list[Trial] = []
    with (
        tempfile.TemporaryDirectory() as folder,
        serve(Path(folder)) as server,
        sync_playwright() as playwright,
    ):
        browser = chromium.launch(playwright)
        pages = [
            ChromiumPhone.on(chromium.phone(playwright, browser, model).new_page(), model)
            for model in ("Pixel 7", "iPhone 13")
        ]
        for trial in range(trials):
            scene = tappable_scene(np.random.default_rng([SEED, trial]))
            rng = np.random.default_rng([SEED, trial, 1])
            results.append(play(server.base_url, pages, scene, rng))
    return results


def tappable_scene(rng: np.random.Generator) -> PhoneScene:
    """A phone scene whose taps, in each photo, are far enough apart to be tapped without
    zooming (:data:`APART`)."""
    while True:
        scene = phone_scene(rng, LANDMARKS)
        taps1 = np.vstack([scene.landmarks1, scene.epipole1])
        if all(
            apart(points, size)
            for points, size in ((taps1, scene.image_size1), (scene.landmarks2, scene.image_size2))
        ):
            return scene


def apart(points: np.ndarray, size: tuple[int, int]) -> bool:
    gaps = np.hypot(*(points[:, None] - points[None]).transpose(2, 0, 1))
    np.fill_diagonal(gaps, np.inf)
    return bool(gaps.min() > APART * np.hypot(*size))


def rate(values: list[bool | None]) -> tuple[str, int]:
    found = counts(values)
    claimed, held = found["claimed"], found["held"]
    return (f"{100 * held / claimed:.1f} %" if claimed else "no region claimed"), claimed


def counts(values: list[bool | None]) -> dict[str, int]:
    """How many regions were claimed and how many held the truth."""
    claimed = [v for v in values if v is not None]
    return {"claimed": len(claimed), "held": sum(claimed)}


def report(results: list[Trial], seconds: float) -> str:
    held, claimed = rate([r.held for r in results])
    held_fixed, claimed_fixed = rate([r.held_fixed for r in results])
    errors = np.array([r.error_px for r in results])
    sigmas = np.concatenate([r.sigmas for r in results])
    axes = [r.axis_px for r in results if r.axis_px is not None]
    table = markdown_table(
        ["rule for each tap's precision", "95 % region holds the truth", "regions claimed"],
        [
            ["the app's (each tap's own, docs/app.md)", f"**{held}**", str(claimed)],
            [
                f"one fixed {OLD_TAP_SIGMA:g} px for every tap",
                held_fixed,
                str(claimed_fixed),
            ],
        ],
    )
    lines = [
        "# Tap precision through the app",
        "",
        "Command: `python benchmarks/taps.py` (from the repository root, in its virtualenv; "
        "`make bench-taps`)",
        "",
        f"- {source_state('backend', 'shared_solver', 'frontend')}",
        f"- {len(results)} searches, seed {SEED}; {seconds:.0f} s",
        f"- Two phones (Pixel 7, iPhone 13) emulated in Chromium, touch input, the app's default "
        f"zoom (the whole photo), no pinch; where a button over the photo lies on a spot, the "
        f"phone first zooms in about the photo's top edge (the wheel, 1.8x a step) until the "
        f"spot is clear of it. Phone scenes (`testbed.phones.phone_scene`), photos "
        f"stored at {STORED_SIDE} px. Photo 1's phone taps its friend and {LANDMARKS} landmarks; "
        f"photo 2's phone cannot see its friend and finds the {LANDMARKS} landmarks. Each tap "
        f"aims at the true spot and misses by a finger: sd per axis uniform in "
        f"{FINGER_CSS[0]:g}-{FINGER_CSS[1]:g} CSS px, drawn per tap. Scenes whose taps come "
        f"closer than {APART:.0%} of the photo's diagonal (about 50 CSS px on the phone) are "
        "drawn again: a person taps such spots zoomed in.",
        "",
        table,
        "",
        f"- Taps zoomed in first, a button over the photo lying on their spot: "
        f"{sum(r.zoomed for r in results)} of {len(results) * (2 * LANDMARKS + 1)}.",
        f"- Sigmas the app sent (stored-photo px): median {np.median(sigmas):.2f}, "
        f"range {sigmas.min():.2f}-{sigmas.max():.2f}.",
        f"- Error of the answer: median {np.median(errors):.1f} px, "
        f"90th percentile {np.percentile(errors, 90):.1f} px; the region's long semi-axis: "
        f"median {np.median(axes):.1f} px."
        if axes
        else "",
        "",
        "A 95 % region should hold the truth about 95 % of the time; with "
        f"{claimed} regions, one standard deviation of the measured rate is "
        f"{100 * np.sqrt(LEVEL * (1 - LEVEL) / max(claimed, 1)):.1f} points.",
    ]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = command_line(__doc__, DEFAULT_OUT)
    parser.add_argument("--trials", type=int, default=200)
    args = parser.parse_args()
    started = time.monotonic()
    results = run(args.trials)
    text = report(results, time.monotonic() - started)
    publish(text, args.out)
    print(
        json.dumps(
            {
                "app": counts([r.held for r in results]),
                "fixed": counts([r.held_fixed for r in results]),
            }
        )
    )


if __name__ == "__main__":
    main()
