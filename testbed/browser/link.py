"""A phone's network as a test cuts and restores it: in Chromium, the DevTools protocol's
offline emulation of the phone's page; in WebKit, whose WebDriver has no network emulation,
a loopback proxy in front of the server (:mod:`.cutproxy`) that the test cuts."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from .chromium_phone import ChromiumPhone
from .cutproxy import cut_proxy
from .phone import Phone

# While cut off, a phone's fetches and crops fail, and the browsers say so.
DROPPED = r"Failed to load resource|ERR_|failed to load|network|Network|Load failed|connection"


@dataclass(frozen=True)
class Link:
    """A phone's network, which the test can cut and restore; ``base_url``: where this phone
    opens the app."""

    base_url: str
    cut: Callable[[], None]
    restore: Callable[[], None]


@contextmanager
def link(phone: Phone, server: str) -> Iterator[Link]:
    """The phone's network to ``server``: in Chromium, the DevTools protocol's offline
    emulation of the phone's page; in WebKit, a proxy."""
    if isinstance(phone, ChromiumPhone):
        session = phone.context.new_cdp_session(phone.page)
        session.send("Network.enable")

        def emulate(cut: bool) -> None:
            unthrottled = {"latency": 0, "downloadThroughput": -1, "uploadThroughput": -1}
            session.send("Network.emulateNetworkConditions", {**unthrottled, "offline": cut})

        yield Link(server, lambda: emulate(True), lambda: emulate(False))
        return
    with cut_proxy(int(server.rsplit(":", 1)[1])) as proxy:
        yield Link(proxy.base_url, proxy.cut, proxy.restore)
