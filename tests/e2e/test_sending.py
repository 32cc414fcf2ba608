"""When a phone sends its taps: a placed tap goes at once, and nothing goes while a finger
drags a landmark; the landmark moved goes once the finger lets go (frontend/src/tapSaver.ts).

Chromium only: WebKitGTK's driver gives no touch input (docs/browsers.md).
"""

from __future__ import annotations

import json
import time
from typing import Any

from playwright.sync_api import Request

from testbed.browser import play
from testbed.browser.chromium_phone import ChromiumPhone
from testbed.browser.phone import Phone, expect

HOLD_S = 1.0  # a finger resting mid-drag: far longer than any wait before sending


def test_nothing_is_sent_while_a_finger_drags_a_landmark(
    server: str, pixel: Phone, iphone: Phone
) -> None:
    starter, _ = play.start_and_join(server, pixel, iphone, photos=True)
    assert isinstance(starter, ChromiumPhone)
    play.cannot_see(starter)
    sent: list[dict[str, Any]] = []

    def taps_sent(request: Request) -> None:
        if request.method == "PUT" and request.url.endswith("/taps"):
            sent.append(json.loads(request.post_data or "{}"))

    def count() -> int:
        starter.evaluate("() => 0")  # Playwright delivers its events while a call is made
        return len(sent)

    starter.page.on("request", taps_sent)
    starter.tap_photo(200, 200)  # placed: sent
    expect(starter.locator('[data-testid="landmark"][data-id="1"]')).to_be_visible()
    starter.wait_for(lambda: count() == 1, "the placed landmark sent")
    play.saved(starter)

    x, y = starter.get_by_test_id("landmark").centre()
    starter.drag((x, y), (x + 60.0, y))  # 60 CSS px to the right, in steps
    time.sleep(HOLD_S)
    assert count() == 1, "taps were sent while the finger was still dragging"
    starter.touch("up")
    starter.wait_for(lambda: count() == 2, "the moved landmark sent")
    play.saved(starter)
    moved = sent[1]["landmarks"][0]
    assert moved["x"] > 200 + 10  # moved right by the drag (60 CSS px, in photo px)
