"""The photo goes up behind the person's back, in each engine: the phone shows its own copy
at once and takes taps on it; with no connection the upload fails with a clear message and
the taps stay on the phone; once the connection is back the photo goes, then the taps, in
that order, and nothing is lost. The phone never downloads its own photo."""

from __future__ import annotations

import math
import re
import time
from pathlib import Path

import pytest

from deploy.replica import serve
from testbed.browser import play
from testbed.browser.link import DROPPED, link
from testbed.browser.phone import Phone, expect

pytestmark = [pytest.mark.engines("chromium", "webkit"), pytest.mark.waits]

# The phone's requests as its browser's resource timing has them: [path, start, end] ms.
REQUESTS = """() => performance.getEntriesByType("resource")
  .map((e) => [new URL(e.name).pathname, e.startTime, e.responseEnd])"""


@pytest.mark.expected_console_errors(DROPPED)
def test_taps_wait_on_the_phone_for_its_photo(pixel: Phone, iphone: Phone, tmp_path: Path) -> None:
    s = play.scene(3, seed=6)
    with serve(tmp_path) as server, link(iphone, server.base_url) as network:
        starter, joiner = pixel, iphone
        play.start_and_join(server.base_url, starter, joiner, joiner_server=network.base_url)
        expect(joiner.get_by_test_id("photo-input")).to_be_attached()

        network.cut()
        # Shown at once, in the stored photo's pixels, and tappable: no upload awaited.
        play.upload(joiner, play.temple(play.PAIR[1]))
        play.mark_friend(joiner, *s.epipole2)
        play.tap_landmarks(joiner, s.landmarks2, online=False)
        # With no connection the upload gives up (after its retries), says so, keeps the taps.
        error = joiner.get_by_test_id("upload-error")
        expect(error).to_contain_text("no connection")
        expect(error).to_contain_text("Your taps are kept")
        expect(joiner.get_by_test_id("upload-retry")).to_be_visible()
        expect(joiner.get_by_test_id("save-state")).not_to_have_attribute("data-state", "saved")

        network.restore()
        back = time.monotonic()
        # Back online, the photo goes by itself (no Retry tapped), then the taps.
        expect(joiner.get_by_test_id("upload-error")).to_have_count(0)
        play.saved(joiner)
        sent_in = time.monotonic() - back
        state = play.session_state(starter)
        requests = joiner.evaluate(REQUESTS)

    assert sent_in < 15, f"the photo and taps took {sent_in:.1f} s once back online"
    assert state["photos"]["joiner"]["width"] == 640
    taps = state["taps"]["joiner"]
    assert [t["id"] for t in taps["landmarks"]] == [1, 2, 3]
    for tap, (x, y) in zip(taps["landmarks"], s.landmarks2, strict=True):
        assert math.hypot(tap["x"] - x, tap["y"] - y) < 2  # where they were tapped
    friend = taps["friend"]
    assert math.hypot(friend["x"] - s.epipole2[0], friend["y"] - s.epipole2[1]) < 2
    photo_puts = [r for r in requests if r[0].endswith("/photo")]
    tap_puts = [r for r in requests if r[0].endswith("/taps")]
    assert photo_puts, requests
    assert tap_puts, requests
    landed = max(end for _, _, end in photo_puts)
    assert all(start >= landed for _, start, _ in tap_puts), "taps sent before the photo landed"
    own = [path for path, _, _ in requests if re.search(r"/photo/joiner$", path)]
    assert own == [], f"the phone downloaded its own photo: {own}"
