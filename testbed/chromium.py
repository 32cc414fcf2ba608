"""Debian's Chromium as the browser tests and the browser benchmarks launch it (`make test`
and `make browser` install the package when missing): no sandbox (root in CI), no GPU, and
nothing that would reach the internet."""

from __future__ import annotations

from typing import Any

CHROMIUM = "/usr/bin/chromium"
FLAGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


def launch(playwright: Any, extra: tuple[str, ...] = ()) -> Any:
    """A headless Chromium browser of ``playwright`` (a ``sync_playwright()`` object)."""
    return playwright.chromium.launch(executable_path=CHROMIUM, args=[*FLAGS, *extra])


def phone(playwright: Any, browser: Any, model: str) -> Any:
    """A new context of ``browser`` emulating Playwright's phone ``model`` (viewport, device
    scale, touch, user agent), speaking English: the app picks the phone's language, and the
    tests read its English words (tests/e2e/test_languages.py sets the others itself)."""
    device = dict(playwright.devices[model])
    device.pop("default_browser_type", None)
    return browser.new_context(**{"locale": "en-US", **device})
