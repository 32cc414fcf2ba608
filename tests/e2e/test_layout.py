"""Layout at phone sizes, in each engine: whatever the bars say, the screen is never wider
than the phone, so every part of the photo can be tapped."""

from __future__ import annotations

from pathlib import Path

import httpx2
import pytest
from phone import Phone, expect

from testbed.loopback import serve

pytestmark = pytest.mark.engines("chromium", "webkit")

TEMPLE = Path(__file__).parents[1] / "data" / "temple"

# What sticks out to the right of the window: [tag, class, right edge] of each element.
WIDER = """() => [...document.querySelectorAll("body *")]
  .filter((element) => element.getBoundingClientRect().right > innerWidth + 0.5)
  .map((element) => [element.tagName.toLowerCase(), String(element.className),
                     Math.round(element.getBoundingClientRect().right)])"""


@pytest.mark.expected_console_errors(r"Failed to load resource|ERR_|blocked")
def test_the_top_bar_never_widens_the_screen(iphone: Phone, tmp_path: Path) -> None:
    """The longest top bar: the friend offline, this phone reconnecting, a save pending."""
    with serve(tmp_path) as server:
        created = httpx2.post(f"{server.base_url}/api/sessions").raise_for_status().json()
        iphone.goto(f"{server.base_url}/join/{created['join_code']}")
        iphone.get_by_test_id("photo-input").set_input_files(TEMPLE / "templeSR0006.png")
        expect(iphone.get_by_test_id("photo-view")).to_have_attribute("data-photo-width", "640")
    # The server is gone: the stream is down, and a tap cannot be saved.
    expect(iphone.get_by_test_id("reconnecting")).to_be_visible()
    iphone.tap_photo(320, 240)
    expect(iphone.get_by_test_id("save-state")).not_to_have_attribute("data-state", "saved")
    assert iphone.evaluate(WIDER) == []
    width = iphone.evaluate("() => innerWidth")
    view = iphone.get_by_test_id("photo-view")
    assert view.evaluate("(view) => view.getBoundingClientRect().width") == width
