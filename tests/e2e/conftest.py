"""Two phones in Debian's Chromium (Playwright), against a real server on loopback."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, BrowserContext, Playwright, sync_playwright

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


@pytest.fixture
def pixel(playwright: Playwright, browser: Browser) -> Iterator[BrowserContext]:
    context = phone(playwright, browser, "Pixel 7")
    yield context
    context.close()


@pytest.fixture
def iphone(playwright: Playwright, browser: Browser) -> Iterator[BrowserContext]:
    context = phone(playwright, browser, "iPhone 13")
    yield context
    context.close()


@pytest.fixture(scope="session")
def screenshots() -> Path:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    return SCREENSHOTS
