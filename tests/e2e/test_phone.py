"""The phone driver itself, in each engine: the window is the phone's, a tap is the input
the engine can give, fingers are touch pointers, errors the page reports are caught.

These pin down what docs/browsers.md says of the engines: should WebKitGTK's driver gain
touch input, the tap test fails and says so.
"""

from __future__ import annotations

import re
from pathlib import Path
from urllib.parse import quote

import pytest
from PIL import Image

from testbed.browser.phone import Phone

pytestmark = pytest.mark.engines("chromium", "webkit")

LISTEN = """() => {
  window.seen = [];
  for (const type of ["touchstart", "touchend", "mousedown", "mouseup", "click"]) {
    addEventListener(type, () => window.seen.push(type), true);
  }
  for (const type of ["pointerdown", "pointerup"]) {
    addEventListener(type, (e) => window.seen.push(`${type}:${e.pointerType}`), true);
  }
}"""


@pytest.mark.device_pixels
def test_the_window_is_the_phones(server: str, iphone: Phone, tmp_path: Path) -> None:
    """Playwright's iPhone 13: a 390 x 844 screen, Safari's bars leave 390 x 664 to the page,
    3 device pixels per CSS pixel; the screenshot is in device pixels."""
    iphone.goto(f"{server}/")
    size = iphone.evaluate("() => [innerWidth, innerHeight, devicePixelRatio]")
    assert size == [390, 664, 3]
    assert iphone.evaluate("() => [screen.width, screen.height]") == [390, 844]
    iphone.screenshot(path=tmp_path / "start.png")
    with Image.open(tmp_path / "start.png") as shot:
        assert shot.size == (390 * 3, 664 * 3)


def test_a_tap_is_what_the_engine_can_give(server: str, iphone: Phone) -> None:
    iphone.goto(f"{server}/")
    iphone.evaluate(LISTEN)
    iphone.locator("h1").tap()
    iphone.wait_for(lambda: "click" in iphone.evaluate("() => window.seen"), "the click")
    seen = iphone.evaluate("() => window.seen")
    if iphone.pointer == "touch":  # a finger: touch events first, then the imitated mouse
        assert seen[:4] == ["pointerdown:touch", "touchstart", "pointerup:touch", "touchend"], seen
        assert seen[4:] == ["mousedown", "mouseup", "click"], seen
    else:  # WebKitGTK's driver: a "touch" pointer arrives as the mouse
        assert seen == ["pointerdown:mouse", "mousedown", "pointerup:mouse", "mouseup", "click"], (
            seen
        )


def test_fingers_are_touch_pointers(server: str, iphone: Phone) -> None:
    """``touch``: Pointer Events of type "touch" in both engines (real touch input in
    Chromium, dispatched by the page in WebKit), which is what the app reads."""
    iphone.goto(f"{server}/")
    iphone.evaluate(LISTEN)
    left, top, _, bottom = iphone.locator("h1").box()
    iphone.touch("down", [(left + 20, (top + bottom) / 2)])
    iphone.touch("up")

    def pointers() -> list[str]:
        return [seen for seen in iphone.evaluate("() => window.seen") if seen.startswith("pointer")]

    iphone.wait_for(lambda: len(pointers()) >= 2, "the lift")
    assert pointers() == ["pointerdown:touch", "pointerup:touch"]


# A page of its own (the app's policy allows no inline script): its button does what a
# faulty page would, from the page's own code, after the load (when WebKit's watcher is in).
FAULTY = """<!doctype html>
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; script-src 'unsafe-inline'">
<button style="width: 200px; height: 80px" onclick="
  console.error('boom');
  setTimeout(() => { throw new Error('later'); }, 0);
  Promise.reject(new Error('nope'));
  const image = new Image();
  image.src = 'http://127.0.0.1:9/blocked.png';
  document.body.append(image);
">fail</button>"""
KINDS = {
    "console.error": "boom",
    "uncaught exception": "later",
    "unhandled rejection": "nope",
    "policy violation": "Content Security Policy",
}
# WebKit's watcher also sees the image fail (as Chromium logs a failed resource).
ALSO = "failed to load http://127.0.0.1:9/blocked.png"


@pytest.mark.expected_console_errors("|".join([*KINDS.values(), re.escape(ALSO)]))
def test_what_the_page_reports_as_errors_is_caught(iphone: Phone) -> None:
    iphone.goto("data:text/html," + quote(FAULTY))
    iphone.locator("button").tap()

    def missed() -> list[str]:
        errors = "\n".join(iphone.console_errors())
        return [kind for kind, pattern in KINDS.items() if not re.search(pattern, errors)]

    try:
        iphone.wait_for(lambda: missed() == [], "every kind of error")
    except AssertionError as failed:
        raise AssertionError(f"{failed}: missed {missed()} in {iphone.console_errors()}") from None
