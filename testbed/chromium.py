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


def phone(playwright: Any, browser: Any, model: str, *, service_workers: bool = False) -> Any:
    """A new context of ``browser`` emulating Playwright's phone ``model`` (viewport, device
    scale, touch, user agent), speaking English: the app picks the phone's language, and the
    tests read its English words (tests/e2e/test_languages.py sets the others itself).

    The app's service worker (its shell, offline) is blocked unless ``service_workers``:
    Playwright's routes do not see what a worker answers, and tests and benchmarks that
    play network faults or time requests should meet the server, as before the worker.
    tests/e2e/test_app_shell.py runs with it."""
    device = dict(playwright.devices[model])
    device.pop("default_browser_type", None)
    workers = "allow" if service_workers else "block"
    return browser.new_context(**{"locale": "en-US", **device}, service_workers=workers)


def whole_photo(page: Any) -> None:
    """The whole photo in view, as a person who taps across it would ask for it: a photo of
    another shape than the screen opens filling it, part of it a drag away (the app's
    openingTransform); a Playwright ``page`` whose photo is shown."""
    button = page.get_by_test_id("fit")
    if button.count() > 0:
        button.tap()
        button.wait_for(state="detached")
