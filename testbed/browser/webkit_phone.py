"""A phone in WebKit: Debian's WebKitGTK MiniBrowser on its own virtual X screen (Xvfb),
driven by WebKitWebDriver through Selenium.

What the engine allows, found on WebKitGTK 2.50 (docs/browsers.md):
- size: ``--full-screen`` hides MiniBrowser's toolbar (whose width is otherwise the
  window's minimum, 447 px), so the page gets the whole window, sized to the phone's
  viewport; GDK_SCALE gives an integer device pixel ratio (3 for an iPhone 13);
- input: the GTK port builds WebKitWebDriver without touch (ENABLE_WEBDRIVER_TOUCH_INTERACTIONS
  is off), so a W3C pointer of type "touch" arrives as the mouse: a tap is pointerdown and
  pointerup of type "mouse", then click, and there is no second finger: zooming is the
  wheel. Fingers (:meth:`WebKitPhone.touch`) are therefore Pointer Events of type "touch"
  that the page dispatches itself (:data:`FINGERS`): the app's one pointer path
  (frontend/src/pointers.ts) gets them as it gets a phone's;
- console: no log endpoint, no WebDriver BiDi, and MiniBrowser's
  --enable-write-console-messages-to-stdout is not applied to the automation view, so a
  small watcher is put into each page after it loads (:data:`WATCH`).
"""

from __future__ import annotations

import contextlib
import glob
import math
import re
import shutil
import time
import warnings
from collections.abc import Generator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import psutil
from PIL import ImageGrab
from pyvirtualdisplay.display import Display
from selenium import webdriver
from selenium.common.exceptions import StaleElementReferenceException
from selenium.webdriver.common.actions import interaction
from selenium.webdriver.common.actions.action_builder import ActionBuilder
from selenium.webdriver.common.actions.pointer_input import PointerInput
from selenium.webdriver.common.actions.wheel_input import WheelInput
from selenium.webdriver.remote.command import Command
from selenium.webdriver.remote.remote_connection import RemoteConnection
from selenium.webdriver.remote.webelement import WebElement
from selenium.webdriver.webkitgtk.options import Options
from selenium.webdriver.webkitgtk.service import Service
from urllib3.exceptions import ReadTimeoutError

from .phone import RESOLVE, Phone, Point, Step, web_origin

# Debian's packages (webkit2gtk-driver, libwebkit2gtk-4.1-0, xvfb); `make test` installs them.
WEBKIT_DRIVER = "/usr/bin/WebKitWebDriver"
MINIBROWSERS = sorted(
    glob.glob("/usr/lib/*-linux-gnu/webkit2gtk-4.1/MiniBrowser")
)  # per architecture
XVFB = "/usr/bin/Xvfb"
PAGE_LOAD_S = 30
# How long any one WebDriver command may take, s. Selenium's own default is no limit, and
# WebKitGTK's web process can deadlock in GStreamer (docs/browsers.md): the command waiting
# on it then never returned, and a CI run waited out its 90 minutes.
COMMAND_S = 60
STALE_TRIES = 5  # finds of an element the page replaced while it was being used
# How long a new window size may take to reach the page, s.
RESIZE_S = 5.0
# One wheel notch of a mouse (px). The app zooms by exp(0.002 * px) per wheel event
# (frontend/src/gestures.ts, wheelFactor), so a notch is a factor of about 1.22.
WHEEL_NOTCH_PX = 100
WHEEL_NOTCH_ZOOM = math.exp(0.002 * WHEEL_NOTCH_PX)

# MiniBrowser's own page of the browser's website data ("Clear all" per kind): its script
# hands "<page id>:<kinds>" to MiniBrowser, which clears those kinds for every site
# (webkit_website_data_manager_clear). The page id is read from a button of the page.
WEBSITE_DATA = "minibrowser-about:data"
# WEBKIT_WEBSITE_DATA_ALL (WebKitGTK 2.50): caches, storage, IndexedDB, cookies, HSTS,
# Cache Storage... Service workers too, in name: an automation (ephemeral) session keeps its
# registrations through it, so :meth:`WebKitPhone.reset` unregisters them itself.
ALL_WEBSITE_DATA = (1 << 14) - 1
# How long clearing the website data may take, s.
CLEAR_S = 10.0
# A file of the app's precache (vite.config.ts) that runs no app: opened on a site to reach
# its service workers, from the worker's precache when the site's server has stopped.
SW_PROBE = "/icon.svg"
UNREGISTER = """async () => {
  if (!navigator.serviceWorker) return 0;  // an error page: the server gone, no worker
  const all = await navigator.serviceWorker.getRegistrations();
  await Promise.all(all.map((registration) => registration.unregister()));
  return all.length;
}"""

# Collects what the page reports as errors into window.__phoneErrors (read by HARVEST).
WATCH = r"""() => {
  if (window.__phoneErrors) return;
  const errors = (window.__phoneErrors = []);
  const text = (value) =>
    value instanceof Error ? `${value.name}: ${value.message}` : String(value);
  const original = console.error;
  console.error = function (...args) {
    errors.push(args.map(text).join(" "));
    return original.apply(this, args);
  };
  addEventListener("error", (event) => {
    const source = event.target && (event.target.src || event.target.href);
    errors.push(event.error ? text(event.error) : event.message || `failed to load ${source}`);
  }, true);
  addEventListener("unhandledrejection", (event) =>
    errors.push(`Unhandled Promise Rejection: ${text(event.reason)}`));
  document.addEventListener("securitypolicyviolation", (event) =>
    errors.push(`Content Security Policy: ${event.violatedDirective} refused ${event.blockedURI}`));
}"""
HARVEST = "() => (window.__phoneErrors ? window.__phoneErrors.splice(0) : [])"

# Fingers the page dispatches as Pointer Events of type "touch", as a phone's browser does: a
# finger's events go to the element it landed on (a touch pointer's implicit capture) and
# bubble from there; the first finger down is the primary one. Not trusted events, so no
# click or imitated mouse follows, and the page cannot capture them (which the app does not).
FINGERS = r"""([kind, points]) => {
  const fingers = (window.__fingers ??= []);
  const send = (type, finger) => {
    const down = type !== "pointerup";
    finger.target.dispatchEvent(new PointerEvent(type, {
      bubbles: true, cancelable: true, composed: true, view: window,
      pointerId: finger.id, pointerType: "touch", isPrimary: finger.primary,
      clientX: finger.x, clientY: finger.y, screenX: finger.x, screenY: finger.y,
      button: type === "pointermove" ? -1 : 0, buttons: down ? 1 : 0,
      width: 20, height: 20, pressure: down ? 0.5 : 0,
    }));
  };
  if (kind === "down") {
    points.forEach(([x, y], i) => {
      const target = document.elementFromPoint(x, y);
      if (!target) throw new Error(`no element at (${x}, ${y}) for finger ${i}`);
      const finger = { id: 100 + i, primary: fingers.length === 0, target, x, y };
      fingers.push(finger);
      send("pointerdown", finger);
    });
  } else if (kind === "move") {
    points.forEach(([x, y], i) => {
      const finger = fingers[i];
      if (!finger) throw new Error(`finger ${i} is not down`);
      Object.assign(finger, { x, y });
      send("pointermove", finger);
    });
  } else {
    for (const finger of fingers.splice(0)) send("pointerup", finger);
  }
}"""


# A sensor held at one reading, as a phone's browser reports it: an event of `type` (of the
# class `name`) with the fields `init` on the window every 16 ms (with `now`, the first at
# once), until held otherwise under the same `key` or the page goes. WebKitGTK 2.50 has
# neither a motion nor an orientation sensor, nor DeviceMotionEvent or DeviceOrientationEvent
# (iOS's WebKit has them): the event is then a plain one with the same fields.
EVERY_16_MS = r"""([key, name, type, init, now]) => {
  clearInterval(window[key]);
  const send = () => {
    const Native = window[name];
    const native = typeof Native === "function" && Native.prototype instanceof Event;
    window.dispatchEvent(native ? new Native(type, init) : Object.assign(new Event(type), init));
  };
  if (now) send();
  window[key] = setInterval(send, 16);
}"""


@dataclass(frozen=True)
class Screen:
    """A phone's screen in CSS px: the page's viewport (the screen less the browser's bars),
    the whole screen, and the device pixel ratio."""

    viewport: tuple[int, int]
    screen: tuple[int, int]
    scale: float


def missing() -> list[str]:
    """The programs a WebKit phone needs that are not installed."""
    absent = [path for path in (WEBKIT_DRIVER, XVFB) if not shutil.which(path)]
    return absent + ([] if MINIBROWSERS else ["MiniBrowser (libwebkit2gtk-4.1-0)"])


class Driver(webdriver.WebKitGTK):
    """WebKitGTK's driver whose commands fail, naming the hang, once one got no answer in
    its time (:data:`COMMAND_S`): the page's process is then stuck, and asking again (the
    fixture's console errors, the pool's reset, quitting) would wait as long each time."""

    hung: str | None = None

    def execute(
        self,
        driver_command: str | Generator[dict[str, Any], Any, Any],
        params: dict[str, Any] | None = None,
    ) -> Any:
        if self.hung is not None:
            raise AssertionError(self.hung)
        try:
            return super().execute(driver_command, params)
        except ReadTimeoutError as timeout:
            executor = self.command_executor
            assert isinstance(executor, RemoteConnection)
            waited = executor.client_config.timeout
            self.hung = (
                f"WebKit gave no answer to {driver_command!r} in {waited:g} s: "
                "its web process is stuck (docs/browsers.md)"
            )
            raise AssertionError(self.hung) from timeout


class WebKitPhone(Phone):
    engine = "webkit"
    pointer = "mouse"

    def __init__(
        self,
        model: str,
        screen: Screen,
        folder: Path,
        turns: bool = False,
        command_s: float = COMMAND_S,
    ) -> None:
        super().__init__(model)
        self.command_s = command_s
        self.viewport = screen.viewport
        absent = missing()
        assert not absent, f"not installed: {absent} (`make test` installs them: `make webkit`)"
        # GTK scales by whole numbers only: 2.625 (a Pixel 7) becomes 3.
        self.scale = max(1, round(screen.scale))
        width, height = screen.screen
        if turns:  # a square screen, as long as the phone's long side: room on its side too
            width = height = max(width, height)
        folder.mkdir(parents=True, exist_ok=True)
        self._display = Display(
            backend="xvfb",
            size=(width * self.scale, height * self.scale),
            color_depth=24,
            manage_global_env=False,
        )
        self._display.start()
        self._errors: list[str] = []
        self._wheels = 0
        # Every site (scheme://host:port) a page was opened on, for reset().
        self._origins: set[str] = set()
        self.closed = False
        try:
            self._driver = self._start(folder)
            self._fit(screen.viewport)
        except BaseException:
            self._display.stop()
            raise

    def _start(self, folder: Path) -> Driver:
        # A home of its own: no profile, cache or storage shared with the other phone.
        home = folder / "home"
        home.mkdir(exist_ok=True)
        environment = self._display.env() | {
            "GDK_BACKEND": "x11",
            "GDK_SCALE": str(self.scale),
            "HOME": str(home),
            "XDG_CACHE_HOME": str(home / "cache"),
            "XDG_CONFIG_HOME": str(home / "config"),
            "XDG_DATA_HOME": str(home / "data"),
            # navigator.languages follows the locale: English, whatever the machine's, since
            # the app speaks the phone's language and the tests read its English words.
            "LANG": "en_US.UTF-8",
            "LANGUAGE": "en_US",
            # No accelerated compositing: Xvfb has no GPU, so WebKit would composite and
            # rasterise through Mesa's software OpenGL (llvmpipe). A phone starting a search
            # and uploading its photo cost 7.9 core-s that way, 3.7 without (docs/browsers.md).
            "WEBKIT_DISABLE_COMPOSITING_MODE": "1",
        }
        options = Options()
        options.binary_location = MINIBROWSERS[0]
        options.add_argument("--automation")
        options.add_argument("--full-screen")  # no toolbar: the page gets the whole window
        # getUserMedia with WebKit's mock cameras (the in-app camera, test_in_app_camera.py).
        options.add_argument("--enable-media-stream=true")
        options.add_argument("--enable-mock-capture-devices=true")
        service = Service(
            executable_path=WEBKIT_DRIVER,
            env=environment,
            log_output=str(folder / "webkitwebdriver.log"),
        )
        with warnings.catch_warnings():
            # Selenium's own WebKitGTK class still sets remote_server_addr, which it deprecates.
            warnings.filterwarnings("ignore", "setting remote_server_addr", DeprecationWarning)
            driver = Driver(options=options, service=service)
        driver.set_page_load_timeout(PAGE_LOAD_S)
        assert isinstance(driver.command_executor, RemoteConnection)
        driver.command_executor.client_config.timeout = self.command_s
        return driver

    def _fit(self, viewport: tuple[int, int]) -> None:
        """The window at the phone's viewport; checked, since GTK may refuse a size."""
        width, height = viewport
        self._driver.set_window_rect(0, 0, width, height)
        got = self.evaluate("() => [innerWidth, innerHeight, devicePixelRatio]")
        assert got == [width, height, self.scale], (
            f"{self}: the page got {got[0]}x{got[1]} at {got[2]}x, "
            f"not {width}x{height} at {self.scale}x"
        )

    def goto(self, url: str) -> None:
        self._harvest()
        self._visit(url)
        self._driver.get(url)
        self.evaluate(WATCH)

    def reload(self) -> None:
        self._harvest()
        self._driver.refresh()
        self.evaluate(WATCH)

    def evaluate(self, script: str, arg: Any = None) -> Any:
        return self._driver.execute_script(f"return ({script})(arguments[0]);", arg)

    def tap_at(self, x: float, y: float) -> None:
        actions = self._finger()
        actions.pointer_action.move_to_location(x, y).pointer_down().pointer_up()
        actions.perform()

    def touch(self, kind: Literal["down", "move", "up"], points: Sequence[Point] = ()) -> None:
        self.evaluate(FINGERS, [kind, [list(point) for point in points]])

    def zoom(self, around: tuple[float, float], factor: float) -> None:
        """Wheel notches at ``around``: up (in) for a factor above 1, down (out) below.

        Two quirks of WebKitWebDriver 2.50 are worked around: a wheel before any pointer
        action in the window is lost (so the finger moves there first, without pressing),
        and a wheel source sends each scroll's difference from its previous one (a second
        notch of the same size scrolls nothing), so every notch gets a source of its own.
        """
        x, y = round(around[0]), round(around[1])
        hover = self._finger()
        hover.pointer_action.move_to_location(x, y)
        hover.perform()
        notches = round(math.log(factor) / math.log(WHEEL_NOTCH_ZOOM))
        delta = -WHEEL_NOTCH_PX if notches > 0 else WHEEL_NOTCH_PX
        for _ in range(abs(notches)):
            self._wheels += 1
            wheel = ActionBuilder(
                self._driver, wheel=WheelInput(f"wheel{self._wheels}"), duration=0
            )
            wheel.wheel_action.scroll(
                x=x, y=y, delta_x=0, delta_y=delta, duration=0, origin="viewport"
            )
            wheel.perform()

    def _finger(self) -> ActionBuilder:
        # A finger does not glide to where it lands: moves take no time.
        finger = PointerInput(interaction.POINTER_TOUCH, "finger")
        return ActionBuilder(self._driver, mouse=finger, duration=0)

    def resize(self, width: int, height: int) -> None:
        # GTK may apply a new size a moment later than asked (a fresh-clone run once read
        # the old size back at once): asked again until the page has it, then checked.
        deadline = time.monotonic() + RESIZE_S
        while time.monotonic() < deadline:
            self._driver.set_window_rect(0, 0, width, height)
            if self.evaluate("() => [innerWidth, innerHeight]") == [width, height]:
                break
            time.sleep(0.2)
        self._fit((width, height))

    def screenshot(self, path: Path) -> None:
        # WebKitGTK's screenshot is the last frame painted, which may not show the latest
        # change yet: two animation frames first.
        self._driver.execute_async_script(
            "const done = arguments[0]; requestAnimationFrame(() => requestAnimationFrame(done));"
        )
        # Read off the phone's X screen: WebDriver's screenshot waits for a composited frame,
        # which never comes with compositing off (_start). The window is at the
        # screen's corner (_fit), the page fills it, and the screen is in device pixels.
        width, height = self.evaluate("() => [innerWidth, innerHeight]")
        box = (0, 0, width * self.scale, height * self.scale)
        ImageGrab.grab(box, xdisplay=self._display.new_display_var).save(path)

    def console_errors(self) -> list[str]:
        self._harvest()
        return list(self._errors)

    def close(self) -> None:
        self.closed = True
        # The browser's processes, listed while the driver is their parent: a stuck web
        # process outlives MiniBrowser's quitting, so whatever is left is killed.
        driver = psutil.Process(self._driver.service.process.pid)
        family = driver.children(recursive=True)
        try:
            self._driver.quit()
        finally:
            self._display.stop()
            for process in family:
                with contextlib.suppress(psutil.NoSuchProcess):
                    process.kill()

    def fill_in(self, steps: tuple[Step, ...], text: str) -> None:
        element = self._element(steps)
        element.clear()
        element.send_keys(text)

    def choose_file(self, steps: tuple[Step, ...], path: Path) -> None:
        # Like Playwright's set_input_files, it waits for the input: the app may render it
        # anew between finding it and sending the file to it (seen in test_upload_behind
        # under load, as a stale element, or a moment with none when the network was cut).
        for attempt in range(STALE_TRIES):
            self.wait_for(lambda: self._found(steps) is not None, f"{steps} to choose a file with")
            try:
                self._element(steps).send_keys(str(path))
                return
            except (StaleElementReferenceException, AssertionError):
                if attempt == STALE_TRIES - 1:
                    raise
                time.sleep(0.1)

    def hold_still(self, acceleration: tuple[float, float, float]) -> None:
        reading = dict(zip("xyz", acceleration, strict=True))
        init = {"accelerationIncludingGravity": reading, "interval": 16}
        self.evaluate(EVERY_16_MS, ["__motion", "DeviceMotionEvent", "devicemotion", init, False])

    def _found(self, steps: tuple[Step, ...]) -> WebElement | None:
        element = self.evaluate(f"(steps) => ({RESOLVE})(steps)[0]", list(steps))
        return element if isinstance(element, WebElement) else None

    def _element(self, steps: tuple[Step, ...]) -> WebElement:
        element = self._found(steps)
        assert element is not None, f"{self}: nothing matches {steps}"
        return element

    def reset(self) -> None:
        """Back to what a new phone is to the app, so the next test may take this one
        (conftest's pool): no page, no website data on any site, the model's window size,
        nothing in the Python state a test could have left. Raises if any of it fails (the
        pool then closes the phone).

        - Service workers (the app's, WebKit runs it) are unregistered on each site opened:
          MiniBrowser's clearing keeps them. The page that asks is :data:`SW_PROBE`, so
          no app runs (which would register one) and a stopped server's site is reached
          through its worker's precache (without a worker there is nothing to do).
        - Everything else, on every site at once (so also those of servers that have
          stopped, whose port a later server may take): MiniBrowser's website data page.
        - The pointer's pressed buttons released (W3C Release Actions). The wheel sources'
          count is kept: a source name used again would scroll by its difference from the
          last scroll (see :meth:`zoom`).
        """
        self._visit(self._driver.current_url)
        for origin in sorted(self._origins):
            self._driver.get(origin + SW_PROBE)
            self.evaluate(UNREGISTER)
        self._driver.get("about:blank")
        self._clear_website_data()
        self._driver.get("about:blank")
        self._driver.execute(Command.W3C_CLEAR_ACTIONS)
        if self.evaluate("() => [innerWidth, innerHeight]") != list(self.viewport):
            self.resize(*self.viewport)
        self._errors.clear()
        self._origins.clear()

    def _clear_website_data(self) -> None:
        """Every kind of website data of every site, through MiniBrowser's page, which shows
        itself again once cleared; then checked on a fresh look at the page."""
        self._driver.get(WEBSITE_DATA)
        listed = re.search(r"clearData\('(\d+):", self._driver.page_source)
        if listed is None:
            return  # nothing stored
        self.evaluate(
            "(message) => window.webkit.messageHandlers.aboutData.postMessage(message)",
            f"{listed[1]}:{ALL_WEBSITE_DATA}",
        )
        deadline = time.monotonic() + CLEAR_S
        while "clearData('" in self._driver.page_source:
            assert time.monotonic() < deadline, f"{self}: website data not cleared"
            time.sleep(0.05)
        self._driver.get("about:blank")
        self._driver.get(WEBSITE_DATA)
        assert "clearData('" not in self._driver.page_source, f"{self}: website data left"

    def _visit(self, url: str) -> None:
        origin = web_origin(url)
        if origin is not None:
            self._origins.add(origin)

    def _harvest(self) -> None:
        """Move what the page's watcher collected into ``_errors`` (before the page goes)."""
        self._errors += self.evaluate(HARVEST)
