"""What a person does with a phone, in Playwright terms: taps on photo pixels, pinches."""

from __future__ import annotations

import math

from playwright.sync_api import BrowserContext, Page

TIMEOUT_MS = 20_000


def photo_to_screen(page: Page, x: float, y: float) -> tuple[float, float]:
    """Client coordinates of photo pixel (x, y), from the view's published transform."""
    view = page.get_by_test_id("photo-view")
    box = view.bounding_box()
    assert box is not None
    scale = float(view.get_attribute("data-scale") or "nan")
    tx = float(view.get_attribute("data-tx") or "nan")
    ty = float(view.get_attribute("data-ty") or "nan")
    return box["x"] + tx + scale * x, box["y"] + ty + scale * y


def tap_photo(page: Page, x: float, y: float) -> None:
    """A one-finger tap on the photo at pixel (x, y)."""
    page.touchscreen.tap(*photo_to_screen(page, x, y))


def pinch(context: BrowserContext, page: Page, around: tuple[float, float], factor: float) -> None:
    """Two fingers spreading (factor > 1) around a client point, in small steps."""
    session = context.new_cdp_session(page)
    cx, cy = around
    start, steps = 40.0, 12

    def fingers(gap: float) -> list[dict[str, float]]:
        half = gap / 2
        return [
            {"x": cx - half / math.sqrt(2), "y": cy - half / math.sqrt(2), "id": 0},
            {"x": cx + half / math.sqrt(2), "y": cy + half / math.sqrt(2), "id": 1},
        ]

    session.send("Input.dispatchTouchEvent", {"type": "touchStart", "touchPoints": fingers(start)})
    for step in range(1, steps + 1):
        gap = start * factor ** (step / steps)
        session.send("Input.dispatchTouchEvent", {"type": "touchMove", "touchPoints": fingers(gap)})
    session.send("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})
    session.detach()
