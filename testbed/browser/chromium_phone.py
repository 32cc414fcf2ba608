"""A phone in Debian's Chromium, driven by Playwright: a mobile-emulated browser context
(viewport, device scale, touch, user agent) with one page; taps, drags and pinches are real
touch input through the DevTools protocol (``Input.dispatchTouchEvent``)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

from playwright.sync_api import Browser, BrowserContext, CDPSession, ElementHandle, Page, Playwright
from playwright.sync_api import Error as PlaywrightError

from testbed import chromium

from .phone import RESOLVE, Phone, Point, Step, web_origin

NAVIGATION_TIMEOUT_MS = 30_000


class ChromiumPhone(Phone):
    engine = "chromium"
    pointer = "touch"

    def __init__(
        self,
        playwright: Playwright | None,
        browser: Browser | None,
        model: str,
        *,
        service_workers: bool = False,
        context: BrowserContext | None = None,
        page: Page | None = None,
    ) -> None:
        """A page of its own in ``context`` (a kept one: chromium_pool.py), else in a new
        context, which :meth:`close` closes; or ``page``, a page of ``context`` made by its
        owner (a benchmark's, its meters on it), which the owner closes."""
        super().__init__(model)
        self._own_context = context is None
        if context is None:
            assert playwright is not None
            assert browser is not None
            context = chromium.phone(playwright, browser, model, service_workers=service_workers)
        self._context: BrowserContext = context
        self._context.set_default_navigation_timeout(NAVIGATION_TIMEOUT_MS)
        self._page = page or self._context.new_page()
        self._errors: list[str] = []
        self._touch: CDPSession | None = None
        self._sensors: chromium.Sensors | None = None  # the sensors whose readings are the test's
        # What a kept context must forget after the test (chromium_pool.py): the sites
        # opened, and whether the test went past this class to the context or the sensors.
        self.origins: set[str] = set()
        self.beyond_the_page = False
        self._page.on("framenavigated", lambda frame: self._opened(web_origin(frame.url)))
        self._page.on(
            "console", lambda m: self._errors.append(m.text) if m.type == "error" else None
        )
        self._page.on("pageerror", lambda error: self._errors.append(str(error)))

    @classmethod
    def on(cls, page: Page, model: str) -> ChromiumPhone:
        """The driver on a page its owner made and closes: a benchmark's, its own meters
        and throttling on it (the phone's ``model``, as its context emulates)."""
        return cls(None, None, model, context=page.context, page=page)

    def _opened(self, origin: str | None) -> None:
        if origin is not None:
            self.origins.add(origin)

    @property
    def context(self) -> BrowserContext:
        """Playwright's context, for what only Chromium has (the DevTools protocol's
        network emulation, say); a test that uses it runs in Chromium only, and its
        context is not kept for another test."""
        self.beyond_the_page = True
        return self._context

    @property
    def page(self) -> Page:
        return self._page

    def navigating(self, error: Exception) -> bool:
        destroyed = "Execution context was destroyed"
        return isinstance(error, PlaywrightError) and destroyed in str(error)

    def goto(self, url: str) -> None:
        self._page.goto(url)

    def reload(self) -> None:
        self._page.reload()

    def evaluate(self, script: str, arg: Any = None) -> Any:
        return self._page.evaluate(script, arg)

    def tap_at(self, x: float, y: float) -> None:
        self._page.touchscreen.tap(x, y)

    def touch(self, kind: Literal["down", "move", "up"], points: Sequence[Point] = ()) -> None:
        self._touch = self._touch or self._context.new_cdp_session(self._page)
        fingers = [{"x": x, "y": y, "id": i} for i, (x, y) in enumerate(points)]
        event = {"down": "touchStart", "move": "touchMove", "up": "touchEnd"}[kind]
        self._touch.send("Input.dispatchTouchEvent", {"type": event, "touchPoints": fingers})

    def resize(self, width: int, height: int) -> None:
        self.page.set_viewport_size({"width": width, "height": height})

    def screenshot(self, path: Path) -> None:
        self._page.screenshot(path=path)

    def console_errors(self) -> list[str]:
        # Playwright's sync API delivers events only while a call is under way: one round
        # trip lets those that arrived since the last call in.
        self._page.evaluate("() => 0")
        return list(self._errors)

    def close(self) -> None:
        if self._own_context:
            self._context.close()
        else:
            self._page.close()

    def fill_in(self, steps: tuple[Step, ...], text: str) -> None:
        self._handle(steps).fill(text)

    def choose_file(self, steps: tuple[Step, ...], path: Path) -> None:
        self._handle(steps).set_input_files(path)

    def hold_still(self, acceleration: tuple[float, float, float]) -> None:
        # Chromium's DeviceMotionEvent reads three sensors; each is overridden (the DevTools
        # protocol's sensor emulation), the still phone's linear acceleration and turn zero.
        # Its motion events then come every 16 ms, their readings rounded to 0.1 m/s^2.
        self.sensors.hold_still(acceleration)

    def hold_orientation(
        self, quaternion: tuple[float, float, float, float], sensor: str = "absolute-orientation"
    ) -> None:
        """The phone's absolute orientation from now on (Chromium's ``absolute-orientation``
        sensor, behind ``deviceorientationabsolute``), or its ``relative-orientation`` (the
        live view's, and the in-app camera's at the shutter): ``quaternion`` (x, y, z, w)
        turns the device frame (x right of the screen, y its top, z out of it) into the
        earth's (x east, y north, z up). Call it first before the page listens (before the
        camera opens); again, and the reading changes."""
        self.sensors.hold_orientation(quaternion, sensor)

    @property
    def sensors(self) -> chromium.Sensors:
        """The page's sensors, the test's from now on (the phone is then not kept)."""
        self.beyond_the_page = True
        self._sensors = self._sensors or chromium.Sensors(self._context, self._page)
        return self._sensors

    def reduce_motion(self) -> None:
        """The phone's "reduce motion" setting on (``prefers-reduced-motion: reduce``)."""
        self._page.emulate_media(reduced_motion="reduce")

    def _handle(self, steps: tuple[Step, ...]) -> ElementHandle:
        handle = self._page.evaluate_handle(f"(steps) => ({RESOLVE})(steps)[0]", list(steps))
        element = handle.as_element()
        assert element is not None, f"{self}: nothing matches {steps}"
        return element
