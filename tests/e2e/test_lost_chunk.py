"""A lazily loaded chunk that does not come (frontend/src/shell/update.ts): with no signal
the page stays where it is (a reload would land on the browser's error page, the session
lost from view); when the server has moved to another build, the page reloads, once.

Chromium (Playwright's routes stand in for the network). The chunk is the share panel's QR
encoder, fetched once a search starts; the server's answer about its build is the page's
request for ``/?build-check=...``. WebKit meets the same path in test_upload_behind.py.
"""

from __future__ import annotations

import re
from collections.abc import Callable

import pytest
from playwright.sync_api import Route

from testbed.browser.chromium_phone import ChromiumPhone
from testbed.browser.phone import Phone, expect

QR_CHUNK = "**/assets/qr-*.js"
BUILD_CHECK = re.compile(r"/\?build-check=\d+$")
# Chromium logs each failed or refused fetch, and an import that failed.
LOST = r"Failed to load resource|Failed to fetch dynamically imported module|ERR_"


def counting(answer: Callable[[Route], None]) -> tuple[list[str], Callable[[Route], None]]:
    """A route handler that answers with ``answer`` and keeps the URL of each request."""
    seen: list[str] = []

    def handle(route: Route) -> None:
        seen.append(route.request.url)
        answer(route)

    return seen, handle


def loads_when_started(phone: ChromiumPhone, server: str, checks: list[str], asked: int) -> int:
    """Start a search; once the page has asked ``asked`` times about its build, how many
    times a page loaded (the first one included)."""
    loads: list[str] = []
    phone.page.on("load", lambda page: loads.append(page.url))
    phone.goto(f"{server}/")
    phone.get_by_test_id("start").tap()
    expect(phone.get_by_test_id("code")).to_have_text(re.compile(r"\d{4}"))

    # (Playwright runs the route handlers only while this thread is in one of its calls.)
    def asked_enough() -> bool:
        phone.page.wait_for_timeout(50)
        return len(checks) >= asked

    phone.wait_for(asked_enough, "the page to ask the server about its build")
    # A reload starts at once (location.reload() as soon as the answer is read): a second
    # lets one show.
    phone.page.wait_for_timeout(1000)
    assert len(checks) == asked, checks
    return len(loads)


@pytest.mark.expected_console_errors(LOST)
def test_a_chunk_lost_to_no_signal_keeps_the_page(pixel: Phone, server: str) -> None:
    assert isinstance(pixel, ChromiumPhone)
    pixel.page.route(QR_CHUNK, lambda route: route.abort("internetdisconnected"))
    checks, no_signal = counting(lambda route: route.abort("internetdisconnected"))
    pixel.page.route(BUILD_CHECK, no_signal)
    assert loads_when_started(pixel, server, checks, asked=1) == 1
    # The search goes on without the QR code: its code and link are there to share.
    expect(pixel.get_by_test_id("waiting")).to_be_visible()
    expect(pixel.get_by_test_id("qr")).to_have_count(0)


@pytest.mark.expected_console_errors(LOST)
def test_a_chunk_of_a_build_gone_reloads_the_page_once(pixel: Phone, server: str) -> None:
    """The server no longer has the chunk (404) and names another entry: the page reloads
    into it. Here the new entry is only named, so the reloaded page fails the same way and
    asks again; it does not reload again within 10 s (no loop)."""
    assert isinstance(pixel, ChromiumPhone)
    pixel.page.route(QR_CHUNK, lambda route: route.fulfill(status=404, body="Not Found"))
    other = '<!doctype html><script type="module" src="/assets/index-ANOTHER.js"></script>'
    checks, other_build = counting(
        lambda route: route.fulfill(body=other, content_type="text/html")
    )
    pixel.page.route(BUILD_CHECK, other_build)
    assert loads_when_started(pixel, server, checks, asked=2) == 2
    # The search survived the reload: its screen is shown again.
    expect(pixel.get_by_test_id("waiting")).to_be_visible()


@pytest.mark.expected_console_errors(LOST)
def test_a_chunk_that_fails_once_on_this_build_keeps_the_page(pixel: Phone, server: str) -> None:
    """The server answers and is on this build (the chunk failed in passing): no reload."""
    assert isinstance(pixel, ChromiumPhone)
    pixel.page.route(QR_CHUNK, lambda route: route.abort("connectionreset"))
    checks, asking = counting(lambda route: route.continue_())
    pixel.page.route(BUILD_CHECK, asking)
    assert loads_when_started(pixel, server, checks, asked=1) == 1
    expect(pixel.get_by_test_id("waiting")).to_be_visible()
