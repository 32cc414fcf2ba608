"""Two phones in Debian's Chromium (Playwright), against a real server on loopback."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, BrowserContext, Page, Playwright, sync_playwright

from backend.loopback import serve

ROOT = Path(__file__).parents[2]
CHROMIUM = "/usr/bin/chromium"  # Debian's package; `make test` installs it when missing
FLAGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    # A venue-like name for loopback (browsers treat "localhost" and 127.0.0.1 as secure even
    # over plain HTTP; a phone on the LAN gets no such favour): tests/e2e/test_https.py.
    "--host-resolver-rules=MAP buddy.test 127.0.0.1",
]
SCREENSHOTS = ROOT / "artifacts" / "screenshots"


@pytest.fixture(scope="session")
def playwright() -> Iterator[Playwright]:
    with sync_playwright() as running:
        yield running


@pytest.fixture(scope="session")
def browser(playwright: Playwright) -> Iterator[Browser]:
    assert (ROOT / "frontend" / "dist" / "index.html").is_file(), "build the app: make test does"
    launched = playwright.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
    yield launched
    launched.close()


@pytest.fixture
def server(tmp_path: Path) -> Iterator[str]:
    with serve(tmp_path) as running:
        yield running.base_url


def phone(playwright: Playwright, browser: Browser, model: str) -> BrowserContext:
    """A mobile-emulated browser context (touch, viewport, user agent) of ``model``."""
    device = dict(playwright.devices[model])
    device.pop("default_browser_type", None)
    return browser.new_context(**device)


def console_errors(context: BrowserContext) -> list[str]:
    """What the context's pages report as errors from now on: console errors (a Content
    Security Policy violation is one) and uncaught exceptions."""
    errors: list[str] = []

    def watch(page: Page) -> None:
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda error: errors.append(str(error)))

    context.on("page", watch)
    return errors


def unexpected(errors: list[str], request: pytest.FixtureRequest) -> list[str]:
    """The errors but those the test expects (``@pytest.mark.expected_console_errors``:
    Chromium logs every 4xx answer to a fetch, a refused join code among them)."""
    marker = request.node.get_closest_marker("expected_console_errors")
    if marker is None:
        return errors
    return [error for error in errors if not re.search(marker.args[0], error)]


@pytest.fixture
def pixel(
    playwright: Playwright, browser: Browser, request: pytest.FixtureRequest
) -> Iterator[BrowserContext]:
    context = phone(playwright, browser, "Pixel 7")
    errors = console_errors(context)
    yield context
    context.close()
    assert unexpected(errors, request) == [], "the Pixel's pages reported errors"


@pytest.fixture
def iphone(
    playwright: Playwright, browser: Browser, request: pytest.FixtureRequest
) -> Iterator[BrowserContext]:
    context = phone(playwright, browser, "iPhone 13")
    errors = console_errors(context)
    yield context
    context.close()
    assert unexpected(errors, request) == [], "the iPhone's pages reported errors"


@pytest.fixture(scope="session")
def screenshots() -> Path:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    return SCREENSHOTS
