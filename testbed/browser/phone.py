"""A phone in the end-to-end tests, whichever browser engine drives it.

The tests speak to a :class:`Phone` (open a page, tap a button or a photo pixel, zoom, choose
a file, read a test id's text or attribute, wait, take a screenshot, read console errors);
``chromium_phone.py`` (Playwright) and ``webkit_phone.py`` (Selenium and WebKitWebDriver)
implement the few things that differ. The words mirror Playwright's (``get_by_test_id``,
``locator``, ``expect(...).to_have_text``) so a test reads the same as before, but finding
elements, reading them and waiting are done here, once, in the page's own JavaScript: both
engines then check exactly the same thing.

Playwright's WebKit build is not used: its download is not reachable here and it is not the
engine Debian ships; Selenium drives Debian's WebKitGTK (see docs/browsers.md).
"""

from __future__ import annotations

import math
import re
import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Literal, TypeVar
from urllib.parse import urlsplit

from . import audit

TIMEOUT_S = 20.0
POLL_S = 0.05
T = TypeVar("T")

# One step of a query: ("css", selector) finds descendants of what was found so far,
# ("text", words) keeps those whose text contains the words (case and spaces ignored, as
# Playwright's has_text), ("first", "") keeps the first.
Step = tuple[str, str]
# A client point (CSS px from the viewport's top-left corner).
Point = tuple[float, float]

# The page's side of every query: the steps -> matching elements, in document order.
RESOLVE = r"""(steps) => {
  let found = [document];
  for (const [kind, value] of steps) {
    if (kind === "css") {
      const all = new Set(found.flatMap((root) => [...root.querySelectorAll(value)]));
      found = [...all].sort((a, b) =>
        a === b ? 0 : a.compareDocumentPosition(b) & Node.DOCUMENT_POSITION_FOLLOWING ? -1 : 1);
    } else if (kind === "text") {
      const squash = (text) => text.replace(/\s+/g, " ").trim().toLowerCase();
      found = found.filter((element) => squash(element.textContent || "").includes(squash(value)));
    } else if (kind === "first") {
      found = found.slice(0, 1);
    }
  }
  return found;
}"""

# What an expectation needs of the first match, in one round trip.
STATE = f"""(steps) => {{
  const found = ({RESOLVE})(steps);
  const element = found[0];
  if (!element) return {{ count: 0 }};
  const rect = element.getBoundingClientRect();
  const style = getComputedStyle(element);
  return {{
    count: found.length,
    visible: rect.width > 0 && rect.height > 0 && style.visibility !== "hidden",
    enabled: !element.disabled && !element.closest("fieldset:disabled"),
    text: element.textContent || "",
    innerText: element.innerText || "",
    attributes: Object.fromEntries(
      element.getAttributeNames().map((name) => [name, element.getAttribute(name)])),
  }};
}}"""

# Where to tap an element, once it can be tapped: the only match, visible, enabled, scrolled
# into view, and the topmost element at its centre (not under a dialog or a loupe).
TAP_POINT = f"""(steps) => {{
  const found = ({RESOLVE})(steps);
  if (found.length !== 1) return {{ count: found.length }};
  const element = found[0];
  let rect = element.getBoundingClientRect();
  if (rect.width === 0 || rect.height === 0) return {{ count: 1, problem: "not visible" }};
  if (element.disabled) return {{ count: 1, problem: "disabled" }};
  if (rect.top < 0 || rect.left < 0 || rect.bottom > innerHeight || rect.right > innerWidth) {{
    element.scrollIntoView({{ block: "center", inline: "center" }});
    rect = element.getBoundingClientRect();
  }}
  const x = rect.left + rect.width / 2;
  const y = rect.top + rect.height / 2;
  const hit = document.elementFromPoint(x, y);
  if (!hit || (hit !== element && !element.contains(hit))) {{
    return {{ count: 1, problem: `covered by <${{hit ? hit.tagName.toLowerCase() : "nothing"}}>` }};
  }}
  return {{ count: 1, x, y, box: [rect.left, rect.top, rect.width, rect.height] }};
}}"""

# The photo view's published transform (PhotoView.tsx): pixel (x, y) of the photo is at
# (left + tx + scale * x, top + ty + scale * y) in client coordinates; none while the view
# glides to an answer (a tap then would land elsewhere).
TRANSFORM = f"""([steps, settled]) => {{
  const element = ({RESOLVE})(steps)[0];
  if (!element || !element.hasAttribute("data-scale")) return null;
  // Moving, or about to (an answer waiting for the fingers' quiet): not yet where it stays.
  if (element.hasAttribute("data-gliding")) return null;
  if (settled && element.hasAttribute("data-settling")) return null;
  const rect = element.getBoundingClientRect();
  const read = (name) => Number(element.getAttribute(name));
  return [rect.left, rect.top, read("data-scale"), read("data-tx"), read("data-ty"),
          rect.width, rect.height];
}}"""


def web_origin(url: str) -> str | None:
    """``scheme://host:port`` of an http(s) ``url``, else None (about:blank, data:): the
    sites whose data a kept phone must clear (webkit_pool.py, chromium_pool.py)."""
    parts = urlsplit(url)
    return f"{parts.scheme}://{parts.netloc}" if parts.scheme in ("http", "https") else None


def _squash(text: str) -> str:
    return re.sub(r"\s+", " ", text).strip()


def _test_id(test_id: str) -> str:
    return '[data-testid="{}"]'.format(test_id.replace("\\", "\\\\").replace('"', '\\"'))


class Phone(ABC):
    """One phone: a browser window of a phone's size showing one page.

    Subclasses implement the engine's part (the abstract methods); everything else is
    written once, here, on top of :meth:`evaluate`.
    """

    #: "chromium" or "webkit".
    engine: ClassVar[str]
    #: What a tap (``tap_at``) is to the page: "touch" (a finger, as on a phone) or "mouse"
    #: (the engine's automation has no touch input: the tap is the mouse's). The app reads
    #: both as Pointer Events, in one code path (frontend/src/pointers.ts); ``touch`` puts
    #: fingers on the page in either engine.
    pointer: ClassVar[Literal["touch", "mouse"]]

    def __init__(self, model: str) -> None:
        self.model = model

    # --- the engine's part ---------------------------------------------------------------

    @abstractmethod
    def goto(self, url: str) -> None:
        """Open ``url`` and wait for its load event."""

    @abstractmethod
    def reload(self) -> None:
        """Reload the page and wait for its load event."""

    @abstractmethod
    def evaluate(self, script: str, arg: Any = None) -> Any:
        """Run the JavaScript function expression ``script`` on ``arg`` (JSON) in the page;
        its JSON result."""

    @abstractmethod
    def tap_at(self, x: float, y: float) -> None:
        """One finger (or the engine's pointer) down and up at client point (x, y)."""

    @abstractmethod
    def touch(self, kind: Literal["down", "move", "up"], points: Sequence[Point] = ()) -> None:
        """Fingers on the page as pointers of type "touch": "down" puts finger i at
        ``points[i]`` (client px), "move" moves them there, "up" lifts them all where they are."""

    @abstractmethod
    def resize(self, width: int, height: int) -> None:
        """The viewport at ``width`` x ``height`` CSS px: the phone turned on its side (the
        sizes swapped) or back upright."""

    @abstractmethod
    def screenshot(self, path: Path) -> None:
        """The visible page as a PNG, at the device's pixel ratio."""

    @abstractmethod
    def console_errors(self) -> list[str]:
        """What the page reported as errors so far: console errors, uncaught exceptions and
        unhandled rejections, Content Security Policy violations."""

    @abstractmethod
    def close(self) -> None:
        """Close the window and whatever the engine started for it."""

    @abstractmethod
    def fill_in(self, steps: tuple[Step, ...], text: str) -> None:
        """Replace the text of the input ``steps`` find by ``text``, as typed."""

    @abstractmethod
    def choose_file(self, steps: tuple[Step, ...], path: Path) -> None:
        """Choose ``path`` in the file input ``steps`` find."""

    @abstractmethod
    def hold_still(self, acceleration: tuple[float, float, float]) -> None:
        """The phone held still from now on: its accelerometer reads ``acceleration`` (m/s^2,
        the device frame of DeviceMotionEvent's ``accelerationIncludingGravity``) on every
        motion event. Call it before the page listens (before the camera opens)."""

    # --- written once -------------------------------------------------------------------

    def get_by_test_id(self, test_id: str) -> Element:
        return Element(self, (("css", _test_id(test_id)),))

    def locator(self, css: str) -> Element:
        return Element(self, (("css", css),))

    def get_by_role(self, role: str) -> Element:
        """Elements with this explicit ``role`` attribute (implicit roles are not derived)."""
        return self.locator(f'[role="{role}"]')

    def navigating(self, error: Exception) -> bool:
        """Whether ``error`` only says the page was being replaced while it was asked (the
        question is then asked again)."""
        return False

    def wait_for(
        self, condition: Callable[[], bool], what: str, timeout: float = TIMEOUT_S
    ) -> None:
        """Poll ``condition`` until it holds; fail naming ``what`` after ``timeout`` s."""
        deadline = time.monotonic() + timeout
        while True:
            try:
                if condition():
                    return
            except Exception as error:
                if not self.navigating(error):
                    raise
            if time.monotonic() > deadline:
                raise AssertionError(f"{self}: timed out after {timeout:g} s waiting for {what}")
            time.sleep(POLL_S)

    def wait_until(
        self,
        read: Callable[[], T],
        holds: Callable[[T], bool],
        what: str,
        timeout: float = TIMEOUT_S,
    ) -> T:
        """Poll ``read`` until its value ``holds``; that value. A failure names ``what`` and
        the last value read, which is what a reader of the failure needs first."""
        last: list[T] = []

        def check() -> bool:
            last[:] = [read()]
            return holds(last[0])

        try:
            self.wait_for(check, what, timeout)
        except AssertionError as failed:
            raise AssertionError(f"{failed}; last: {last[-1:]}") from None
        return last[0]

    def photo_to_screen(self, x: float, y: float, *, settled: bool = True) -> tuple[float, float]:
        """Client coordinates of photo pixel (x, y), from the view's published transform
        (:meth:`view_box`)."""
        left, top, scale, tx, ty, _, _ = self.view_box(settled=settled)
        return left + tx + scale * x, top + ty + scale * y

    def view_box(self, *, settled: bool = True) -> list[float]:
        """The photo view's rect and transform once published and not gliding: left, top,
        scale, tx, ty, width, height. ``settled``: nor about to glide (an answer that came
        waits for the fingers' quiet, then glides the view to it); False reads the view as
        a finger about to tap finds it, which the glide would move after a wait."""
        steps = list(self.get_by_test_id("photo-view").steps)
        transform: list[float] = self.wait_until(
            lambda: self.evaluate(TRANSFORM, [steps, settled]),
            lambda found: found is not None,
            "the photo view's transform",
        )
        return transform

    def tap_photo(self, x: float, y: float) -> None:
        """A one-finger tap on the photo at pixel (x, y); first, as a person would, the whole
        photo ("Whole photo") when the view is zoomed or moved and the pixel is out of it."""
        left, top, scale, tx, ty, width, height = self.view_box()
        at = (left + tx + scale * x, top + ty + scale * y)
        seen = left < at[0] < left + width and top < at[1] < top + height
        if not seen and self.whole_photo():
            at = self.photo_to_screen(x, y)
        self.tap_at(*at)

    def whole_photo(self) -> bool:
        """The whole photo in view, as a person who taps across it asks for it ("Whole
        photo": a photo of another shape than the screen opens filling it, part of it a
        drag away); whether it had to be asked for."""
        fit = self.get_by_test_id("fit")
        if fit.count() == 0:
            return False
        fit.tap()
        self.wait_for(lambda: fit.count() == 0, "the whole photo")
        return True

    def photo_size(self) -> tuple[float, float]:
        """The width and height (px) of the photo the photo view shows."""
        width, height = self.get_by_test_id("photo-view").numbers("photo-width", "photo-height")
        return width, height

    def drag(self, start: Point, end: Point, steps: int = 10) -> None:
        """One finger down at ``start`` and moved to ``end`` in ``steps`` even steps (client
        px); it stays down: ``touch("up")`` lifts it."""
        (x0, y0), (x1, y1) = start, end
        self.touch("down", [start])
        for k in range(1, steps + 1):
            self.touch("move", [(x0 + (x1 - x0) * k / steps, y0 + (y1 - y0) * k / steps)])

    def zoom(self, around: tuple[float, float], factor: float) -> None:
        """Zoom the photo by about ``factor`` about a client point, as a person would on
        this engine: a two-finger pinch (here) where there is touch input, else the wheel."""
        self.pinch(around, factor)

    def pinch(self, around: Point, factor: float, steps: int = 12) -> None:
        """Two fingers spreading (factor > 1) or closing around a client point, in steps,
        then lifted."""
        cx, cy = around

        def fingers(gap: float) -> list[Point]:
            half = gap / 2 / math.sqrt(2)  # along the diagonal
            return [(cx - half, cy - half), (cx + half, cy + half)]

        start = 40.0
        self.touch("down", fingers(start))
        for k in range(1, steps + 1):
            self.touch("move", fingers(start * factor ** (k / steps)))
        self.touch("up")

    def audit(self, screen: str) -> None:
        """The accessibility audit (axe-core, ``audit.py``) of the page as it is now: fails
        on a serious or critical violation, naming ``screen``."""
        audit.audit(self, screen)

    def __str__(self) -> str:
        return f"{self.model} ({self.engine})"


@dataclass(frozen=True)
class Element:
    """The elements a chain of steps finds on one phone's page, found anew at every use
    (like a Playwright locator)."""

    phone: Phone
    steps: tuple[Step, ...]

    def locator(self, css: str) -> Element:
        return Element(self.phone, (*self.steps, ("css", css)))

    def filter(self, has_text: str) -> Element:
        return Element(self.phone, (*self.steps, ("text", has_text)))

    @property
    def first(self) -> Element:
        return Element(self.phone, (*self.steps, ("first", "")))

    def state(self) -> dict[str, Any]:
        state: dict[str, Any] = self.phone.evaluate(STATE, list(self.steps))
        return state

    def count(self) -> int:
        return int(self.state()["count"])

    def _one(self, what: str) -> dict[str, Any]:
        """The state of the only match, once there is one (several are an error at once,
        as in Playwright's strict mode)."""
        return Expectation(self)._until(lambda s: s["count"] == 1, what)

    def inner_text(self) -> str:
        return str(self._one("exist")["innerText"])

    def get_attribute(self, name: str) -> str | None:
        value = self._one("exist")["attributes"].get(name)
        return None if value is None else str(value)

    def numbers(self, *names: str) -> list[float]:
        """The ``data-{name}`` attributes as numbers, read in one look (so they agree with
        each other), NaN where one is missing: how the page publishes what it draws."""
        attributes = self._one("exist")["attributes"]
        return [float(attributes.get(f"data-{name}") or "nan") for name in names]

    def box(self) -> tuple[float, float, float, float]:
        """The only match's box on the screen, client px: left, top, right, bottom."""
        left, top, right, bottom = self.evaluate(
            "(e) => { const r = e.getBoundingClientRect();"
            " return [r.left, r.top, r.right, r.bottom]; }"
        )
        return float(left), float(top), float(right), float(bottom)

    def centre(self) -> tuple[float, float]:
        """The middle of :meth:`box`, client px: where a finger aims at the element."""
        left, top, right, bottom = self.box()
        return (left + right) / 2, (top + bottom) / 2

    def evaluate(self, script: str) -> Any:
        """Run the JavaScript function expression ``script`` on the only match."""
        self._one("exist")
        call = f"(steps) => ({script})(({RESOLVE})(steps)[0])"
        return self.phone.evaluate(call, list(self.steps))

    def tap(self) -> None:
        """A tap at the element's centre once it can be tapped (see ``TAP_POINT``); the
        element must hold still over two looks, so a moving one is not missed."""
        before: list[Any] = [None]  # the box of the look before

        def look() -> dict[str, Any]:
            found: dict[str, Any] = self.phone.evaluate(TAP_POINT, list(self.steps))
            if found["count"] > 1:
                raise AssertionError(f"{self}: {found['count']} elements match")
            found["still"] = "box" in found and before[0] == found["box"]
            before[0] = found.get("box")
            return found

        at = self.phone.wait_until(look, lambda found: found["still"], f"{self} to be tappable")
        self.phone.tap_at(at["x"], at["y"])

    def fill(self, text: str) -> None:
        self._one("exist")
        self.phone.fill_in(self.steps, text)

    def set_input_files(self, path: Path) -> None:
        self._one("exist")
        self.phone.choose_file(self.steps, path)

    def __str__(self) -> str:
        described = " ".join(
            value if kind == "css" else f"{kind}={value!r}" for kind, value in self.steps
        )
        return f"{self.phone}: {described}"


def expect(element: Element) -> Expectation:
    """Assertions that wait (up to :data:`TIMEOUT_S`) for the page to agree."""
    return Expectation(element)


@dataclass(frozen=True)
class Expectation:
    element: Element

    def _until(
        self, holds: Callable[[dict[str, Any]], bool], what: str, strict: bool = True
    ) -> dict[str, Any]:
        """Until the first match's state ``holds`` (several matches are an error at once when
        ``strict``); that state."""

        def look() -> dict[str, Any]:
            state = self.element.state()
            if strict and state["count"] > 1:
                raise AssertionError(f"{self.element}: {state['count']} elements match")
            return state

        return self.element.phone.wait_until(look, holds, f"{self.element} to {what}")

    def to_be_attached(self) -> None:
        self._until(lambda s: s["count"] == 1, "be attached")

    def to_be_visible(self) -> None:
        self._until(lambda s: s["count"] == 1 and s["visible"], "be visible")

    def to_be_hidden(self) -> None:
        self._until(lambda s: s["count"] == 0 or not s["visible"], "be hidden")

    def to_be_enabled(self) -> None:
        self._until(lambda s: s["count"] == 1 and s["enabled"], "be enabled")

    def to_have_count(self, count: int) -> None:
        self._until(lambda s: s["count"] == count, f"number {count}", strict=False)

    def to_have_text(self, expected: str | re.Pattern[str]) -> None:
        self._until(
            lambda s: s["count"] == 1 and _matches(s["text"], expected), f"read {expected!r}"
        )

    def not_to_have_text(self, expected: str | re.Pattern[str]) -> None:
        self._until(
            lambda s: s["count"] == 1 and not _matches(s["text"], expected),
            f"not read {expected!r}",
        )

    def to_contain_text(self, expected: str) -> None:
        self._until(
            lambda s: s["count"] == 1 and _squash(expected) in _squash(s["text"]),
            f"contain {expected!r}",
        )

    def to_have_attribute(self, name: str, value: str | re.Pattern[str]) -> None:
        self._until(
            lambda s: s["count"] == 1 and _has_attribute(s, name, value), f"have {name}={value!r}"
        )

    def not_to_have_attribute(self, name: str, value: str | re.Pattern[str]) -> None:
        self._until(
            lambda s: s["count"] == 1 and not _has_attribute(s, name, value),
            f"not have {name}={value!r}",
        )


def _has_attribute(state: dict[str, Any], name: str, value: str | re.Pattern[str]) -> bool:
    found = state.get("attributes", {}).get(name)
    return found is not None and _matches(found, value, squash=False)


def _matches(text: str, expected: str | re.Pattern[str], squash: bool = True) -> bool:
    """Playwright's rule: a string matches the whole text (spaces squashed), a pattern
    anywhere in it."""
    if isinstance(expected, re.Pattern):
        return expected.search(text) is not None
    return (_squash(text) == _squash(expected)) if squash else text == expected
