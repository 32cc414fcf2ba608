"""Layout at phone sizes, in each engine: whatever the bars say, the screen is never wider
than the phone, so every part of the photo can be tapped; the photo takes the screen."""

from __future__ import annotations

from pathlib import Path

import httpx2
import pytest
from phone import Phone, expect
from PIL import Image
from test_two_phones import start_and_join

from deploy.replica import serve

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


def test_the_photo_takes_the_screen(
    server: str, pixel: Phone, iphone: Phone, tmp_path: Path, screenshots: Path
) -> None:
    """Full-bleed: the photo view is the whole width and most of the height; a portrait
    photo uses the height, a landscape one the width."""
    _, joiner = start_and_join(server, pixel, iphone)
    portrait = tmp_path / "portrait.png"
    with Image.open(TEMPLE / "templeSR0006.png") as photo:
        photo.transpose(Image.Transpose.ROTATE_90).save(portrait)
    joiner.get_by_test_id("photo-input").set_input_files(portrait)
    view = joiner.get_by_test_id("photo-view")
    expect(view).to_have_attribute("data-photo-height", "640")
    width, height, scale = view.evaluate(
        """(view) => { const r = view.getBoundingClientRect();
            return [r.width, r.height, Number(view.getAttribute("data-scale"))]; }"""
    )
    assert width == joiner.evaluate("() => innerWidth")
    assert height >= 0.65 * joiner.evaluate("() => innerHeight")
    # Fitted: the photo fills the view along one side, the height for this one.
    assert 640 * scale == pytest.approx(height, abs=1) or 480 * scale == pytest.approx(width, abs=1)
    assert 640 * scale >= 0.6 * joiner.evaluate("() => innerHeight")
    joiner.screenshot(path=screenshots / "3b-portrait-photo-joiner.png")
