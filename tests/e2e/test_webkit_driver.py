"""The WebKit phone's driver when the page's process stops answering, as WebKitGTK's did
when a camera view closed (docs/browsers.md): the command fails within the phone's time,
naming the hang, every later command fails at once, and closing the phone leaves no
process of its browser behind."""

from __future__ import annotations

import time
from pathlib import Path

import psutil
import pytest

from testbed.browser.webkit_phone import Screen, WebKitPhone

# A page that stops answering a moment after it was asked to: its script never ends.
STUCK = "() => { setTimeout(() => { for (;;) {} }, 300); }"
COMMAND_S = 3.0


def test_a_stuck_page_fails_its_command_in_time_and_leaves_nothing(tmp_path: Path) -> None:
    screen = Screen((412, 839), (412, 915), 1.0)
    phone = WebKitPhone("Pixel 7", screen, tmp_path, command_s=COMMAND_S)
    try:
        phone.goto("about:blank")
        browser = psutil.Process(phone._driver.service.process.pid).children(recursive=True)
        assert any("MiniBrowser" in " ".join(process.cmdline()) for process in browser)
        phone.evaluate(STUCK)
        time.sleep(0.5)
        started = time.monotonic()
        with pytest.raises(AssertionError, match=r"no answer .* in 3 s: its web process is stuck"):
            phone.evaluate("() => 1")
        assert COMMAND_S <= time.monotonic() - started < COMMAND_S + 5
        started = time.monotonic()
        with pytest.raises(AssertionError, match="stuck"):
            phone.console_errors()
        assert time.monotonic() - started < 1
    finally:
        phone.close()
    _, alive = psutil.wait_procs(browser, timeout=5)
    assert alive == [], alive
