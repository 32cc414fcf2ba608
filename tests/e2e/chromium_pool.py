"""Chromium phones' browser contexts kept for the next test, as webkit_pool.py keeps WebKit
phones: a phone in a new context cost the machine 3.5-4.1 core-s (Chromium starts a renderer
process for it), and 1.8-2.2 in a kept one (a phone opening the app and starting a search,
measured over the whole machine).

A kept context holds a *keeper* page on the worker's server (its app icon): Chromium then
runs the next test's page, on any 127.0.0.1 port, in the keeper's renderer process rather
than starting one. Each test gets a new page of its own; at the test's end its pages are
closed and the context is reset (no cookies, no permissions, nothing stored by any site it
visited, an empty HTTP cache) and kept, or closed when it cannot be trusted to be as new:
its test failed, or reached for the context itself (``ChromiumPhone.context``: offline,
routes, DevTools sessions, init scripts), or emulated sensors.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

from playwright.sync_api import Browser, BrowserContext, CDPSession, Page, Playwright

from testbed import chromium


@dataclass
class Kept:
    """A pooled context, its keeper page and a DevTools session on that page."""

    context: BrowserContext
    keeper: Page
    devtools: CDPSession


@dataclass
class ChromiumPool:
    """Free contexts by phone model; ``keep_at``: the URL every keeper page shows."""

    playwright: Playwright
    browser: Browser
    keep_at: str
    free: dict[str, list[Kept]] = field(default_factory=dict)

    def take(self, model: str) -> Kept:
        """A free context emulating ``model``, else a new one."""
        kept = self.free.get(model)
        if kept:
            return kept.pop()
        context = chromium.phone(self.playwright, self.browser, model)
        keeper = context.new_page()
        keeper.goto(self.keep_at)
        return Kept(context, keeper, context.new_cdp_session(keeper))

    def give_back(self, model: str, kept: Kept, origins: set[str], reuse: bool) -> None:
        """Reset ``kept`` (``origins``: the sites its test's pages opened) and keep it if
        ``reuse`` and the reset succeeds; else close it."""
        if reuse:
            try:
                _reset(kept, origins, self.keep_at)
            except Exception as failed:  # any failure: the context is not kept
                said = f"a {model} context not kept: its reset failed: {failed!r}"
                warnings.warn(said, stacklevel=2)
            else:
                self.free.setdefault(model, []).append(kept)
                return
        kept.context.close()

    def close(self) -> None:
        for contexts in self.free.values():
            for kept in contexts:
                kept.context.close()
        self.free.clear()


def _reset(kept: Kept, origins: set[str], keep_at: str) -> None:
    """Back to what a new context is to the app; raises if any of it fails."""
    for page in kept.context.pages:
        if page is not kept.keeper:
            page.close()
    kept.context.clear_cookies()
    kept.context.clear_permissions()
    for origin in sorted(origins):
        # Local and session storage, IndexedDB, the Cache API, service workers, cookies.
        kept.devtools.send("Storage.clearDataForOrigin", {"origin": origin, "storageTypes": "all"})
    kept.devtools.send("Network.clearBrowserCache")
    shown = kept.keeper.evaluate("() => location.href")
    assert shown == keep_at, f"the keeper page moved: {shown}"
