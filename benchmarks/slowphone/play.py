"""One phone's run at one CPU throttling rate: a Pixel 7 in Chromium opens the app's start
screen, joins a session through its link, picks a photo and taps landmarks on it, each
moment stamped in the page (``watch``).

The CPU is slowed through the DevTools protocol (``Emulation.setCPUThrottlingRate``) from
before the app loads: Chromium then stretches the page's main thread's tasks by the rate.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import httpx2
from playwright.sync_api import Browser, BrowserContext, Page, Playwright, Request, expect

from testbed import chromium
from testbed.browser.chromium_phone import ChromiumPhone
from testbed.client import start

from .watch import AWAIT, INIT, stamps

MODEL = "Pixel 7"
WAIT_MS = 60_000
# Where the taps land, as fractions of the photo's width and height: apart on the screen
# (a tap on a landmark's number selects it instead of placing a new one), none near an edge.
SPOTS = ((0.25, 0.3), (0.75, 0.3), (0.5, 0.5), (0.25, 0.7), (0.75, 0.7))
# The events of a tap in the browser's Event Timing.
TAP_EVENTS = ("pointerdown", "pointerup", "click", "touchstart", "touchend", "mousedown", "mouseup")
SETTLE_MS = 300  # the last Event Timing entries are reported after their paint


@dataclass(frozen=True)
class SlowestEvent:
    """A tap's slowest event as the browser's Event Timing measured it (Interaction to Next
    Paint's parts), ms: its wait for the main thread, its handlers, and its whole duration
    to the next paint (rounded by the browser to 8 ms)."""

    name: str
    waited: float
    handlers: float
    duration: float


@dataclass(frozen=True)
class Tap:
    down_ms: float  # pointerdown -> the mark painted
    lifted_ms: float  # pointerup -> the mark painted
    slowest: SlowestEvent | None  # None: every event under Event Timing's 16 ms threshold


@dataclass
class PhoneRun:
    """What one run measured (ms) and the scripts the page fetched (URL paths)."""

    rate: float
    photo: str
    start_screen_ms: float  # navigation -> the start screen's first contentful paint
    tappable_ms: float = float("nan")  # the photo chosen -> on screen, taking taps
    taps: list[Tap] = field(default_factory=list)
    start_scripts: set[str] = field(default_factory=set)  # fetched for the start screen
    scripts: set[str] = field(default_factory=set)  # ... and for the tap screen


def _session(server: str) -> str:
    """A new session's join code (started over the API: the phone under test joins it)."""
    with httpx2.Client(base_url=server, timeout=30) as http:
        return start(http)[1]


def _phone(playwright: Playwright, browser: Browser, rate: float) -> tuple[BrowserContext, Page]:
    context: BrowserContext = chromium.phone(playwright, browser, MODEL)
    context.add_init_script(INIT)
    page = context.new_page()
    cdp = context.new_cdp_session(page)
    cdp.send("Emulation.setCPUThrottlingRate", {"rate": rate})
    return context, page


def _script(request: Request) -> str | None:
    """The path of a script the page fetched."""
    path = urlsplit(request.url).path
    return path if request.resource_type == "script" or path.endswith(".js") else None


def _assets(scripts: set[str]) -> set[str]:
    """The app's own scripts (its build's ``/assets``) among ``scripts``."""
    return {path for path in scripts if path.startswith("/assets/")}


def _taps(stamped: dict[str, Any]) -> list[Tap]:
    """Each tap's times, with its slowest event in the browser's Event Timing."""
    taps = []
    for tap in stamped["taps"]:
        events = [
            e
            for e in stamped["events"]
            if e["name"] in TAP_EVENTS and tap["down"] - 1 <= e["start"] <= tap["painted"]
        ]
        slowest = max(events, key=lambda e: e["duration"], default=None)
        taps.append(
            Tap(
                tap["painted"] - tap["down"],
                tap["painted"] - tap["lifted"],
                SlowestEvent(
                    slowest["name"],
                    slowest["processingStart"] - slowest["start"],
                    slowest["processingEnd"] - slowest["processingStart"],
                    slowest["duration"],
                )
                if slowest
                else None,
            )
        )
    return taps


def play(
    playwright: Playwright, browser: Browser, server: str, rate: float, photo: tuple[str, Path]
) -> PhoneRun:
    """One run at ``rate`` on a fresh phone (nothing cached): the start screen, then the
    join link, then ``photo`` (its name and file) picked and tapped on."""
    expect.set_options(timeout=WAIT_MS)
    context, page = _phone(playwright, browser, rate)
    with context:
        scripts: set[str] = set()
        page.on("request", lambda r: scripts.add(path) if (path := _script(r)) else None)
        page.goto(f"{server}/")
        expect(page.get_by_test_id("start")).to_be_visible()
        page.wait_for_load_state("networkidle")  # a lazy chunk the screen asks for, too
        paint = page.evaluate(
            "() => performance.getEntriesByName('first-contentful-paint')[0]?.startTime ?? null"
        )
        run = PhoneRun(rate, photo[0], float("nan") if paint is None else float(paint))
        run.start_scripts = _assets(scripts)
        page.goto(f"{server}/join/{_session(server)}")
        expect(page.get_by_test_id("photo-input")).to_be_attached()
        page.get_by_test_id("photo-input").set_input_files(photo[1])
        page.evaluate(AWAIT, "tappable")
        shown = stamps(page)
        run.tappable_ms = shown["tappable"] - shown["chosen"]
        # A person looks at the photo before tapping: its upload has ended by then.
        expect(page.get_by_test_id("save-state")).to_have_attribute("data-state", "saved")
        page.get_by_test_id("cannot-see").tap()  # the joiner cannot see the starter
        phone = ChromiumPhone.on(page, MODEL)
        phone.whole_photo()
        width, height = phone.photo_size()
        for fx, fy in SPOTS:
            phone.tap_photo(fx * width, fy * height)
            page.evaluate(AWAIT, "painted")
        page.wait_for_timeout(SETTLE_MS)
        run.taps = _taps(stamps(page))
        run.scripts = _assets(scripts)
        return run
