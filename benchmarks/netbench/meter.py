"""A phone's network through Chromium's DevTools protocol: the profile it is emulated on
(``Network.emulateNetworkConditions``) and the bytes it sent and received (``Network``
events), on a CDP session of Playwright's.

Bytes are counted on the wire as Chromium reports them: received, a request's
``encodedDataLength`` when it finished (headers and body as they came), else (an event stream
still open) its response headers plus every chunk so far; sent, the request line, the headers
Chromium sent (``requestWillBeSentExtraInfo``) and the body (its ``Content-Length``).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import urlsplit

from playwright.sync_api import BrowserContext, CDPSession, Page

from testbed.client import server_timing


@dataclass(frozen=True)
class Profile:
    """A network: its name, and the conditions to emulate (None: loopback, as it is). The
    round trip is the phone's path's (``link.py``); Chromium limits the throughput."""

    name: str
    up_mbit: float | None = None
    down_mbit: float | None = None
    round_trip_ms: float = 0.0

    def conditions(self) -> dict[str, Any] | None:
        if self.up_mbit is None or self.down_mbit is None:
            return None
        # The protocol takes bytes per second. Its "latency" (added to a request's response
        # only) stays 0: the link delays both directions of every connection instead.
        return {
            "offline": False,
            "latency": 0,
            "downloadThroughput": self.down_mbit * 1e6 / 8,
            "uploadThroughput": self.up_mbit * 1e6 / 8,
        }

    def describe(self) -> str:
        if self.conditions() is None:
            return "loopback (no emulation)"
        return (
            f"{self.up_mbit:g} Mbit/s up, {self.down_mbit:g} Mbit/s down, "
            f"{self.round_trip_ms:g} ms round trip"
        )


LOOPBACK = Profile("loopback")
VENUE = Profile("venue", up_mbit=1.5, down_mbit=3.0, round_trip_ms=300.0)
PROFILES = {profile.name: profile for profile in (LOOPBACK, VENUE)}


@dataclass
class _Request:
    url: str = ""
    method: str = "GET"
    sent_at: float = 0.0  # wall clock, ms since the epoch
    server_ms: float | None = None  # the app's own time (its Server-Timing)
    sent_headers: int = 0
    body: int = 0
    response_headers: int = 0
    chunks: int = 0
    finished: int | None = None
    failed: bool = False

    @property
    def sent(self) -> int:
        target = urlsplit(self.url)
        line = (
            f"{self.method} {target.path}{'?' + target.query if target.query else ''} HTTP/1.1\r\n"
        )
        return len(line) + self.sent_headers + self.body

    @property
    def received(self) -> int:
        return self.finished if self.finished is not None else self.response_headers + self.chunks


@dataclass
class Meter:
    """One page's network: emulated as ``profile`` from :meth:`attach` on, and counted, with
    when each request left and each event of a stream came (wall clock, ms)."""

    profile: Profile
    session: CDPSession | None = None
    requests: dict[str, _Request] = field(default_factory=dict)
    events: list[tuple[str, float]] = field(default_factory=list)  # (type, when)
    # The protocol stamps with a monotonic clock, and a request's departure also with the
    # wall clock: their difference turns the one into the other.
    _wall_offset: float | None = None

    def attach(self, context: BrowserContext, page: Page) -> None:
        session = context.new_cdp_session(page)
        session.send("Network.enable")
        conditions = self.profile.conditions()
        if conditions is not None:
            session.send("Network.emulateNetworkConditions", conditions)
        session.on("Network.requestWillBeSent", self._will_be_sent)
        session.on("Network.requestWillBeSentExtraInfo", self._sent_headers)
        session.on("Network.responseReceived", self._response)
        session.on("Network.dataReceived", self._data)
        session.on("Network.loadingFinished", self._finished)
        session.on("Network.loadingFailed", self._failed)
        session.on("Network.eventSourceMessageReceived", self._event)
        self.session = session

    def _request(self, event: dict[str, Any]) -> _Request:
        return self.requests.setdefault(event["requestId"], _Request())

    def _will_be_sent(self, event: dict[str, Any]) -> None:
        request = self._request(event)
        request.url = event["request"]["url"]
        request.method = event["request"]["method"]
        request.sent_at = event["wallTime"] * 1000
        self._wall_offset = event["wallTime"] - event["timestamp"]

    def _sent_headers(self, event: dict[str, Any]) -> None:
        request = self._request(event)
        headers: dict[str, str] = event.get("headers", {})
        request.sent_headers = sum(len(k) + len(v) + 4 for k, v in headers.items()) + 2
        lengths = [v for k, v in headers.items() if k.lower() == "content-length"]
        request.body = int(lengths[0]) if lengths else 0

    def _response(self, event: dict[str, Any]) -> None:
        request = self._request(event)
        request.response_headers = int(event["response"].get("encodedDataLength", 0))
        headers = {k.lower(): v for k, v in event["response"].get("headers", {}).items()}
        if timing := headers.get("server-timing"):  # app;dur=<ms>, db;dur=<ms>
            request.server_ms = server_timing(timing)["app"]

    def _event(self, event: dict[str, Any]) -> None:
        if self._wall_offset is not None:
            self.events.append(
                (event["eventName"], (event["timestamp"] + self._wall_offset) * 1000)
            )

    def first_sent(self, method: str, path_end: str, after: float) -> _Request:
        """The first ``method`` request to a path ending in ``path_end`` sent after ``after``
        (wall clock, ms)."""
        return min(
            (
                r
                for r in self.requests.values()
                if r.method == method
                and urlsplit(r.url).path.endswith(path_end)
                and r.sent_at >= after
            ),
            key=lambda r: r.sent_at,
        )

    def first_event(self, type_: str, after: float) -> float:
        """When the first event ``type_`` came after ``after`` (wall clock, ms)."""
        return min(when for name, when in self.events if name == type_ and when >= after)

    def _data(self, event: dict[str, Any]) -> None:
        self._request(event).chunks += int(event.get("encodedDataLength", 0))

    def _finished(self, event: dict[str, Any]) -> None:
        self._request(event).finished = int(event.get("encodedDataLength", 0))

    def _failed(self, event: dict[str, Any]) -> None:
        self._request(event).failed = True

    def _fetched(self) -> list[_Request]:
        """The requests over HTTP (not the page's own ``data:`` and ``blob:`` URLs)."""
        return [r for r in self.requests.values() if r.url.startswith("http")]

    def waiting(self) -> list[str]:
        """The requests on their way (event streams aside: they stay open), by path."""
        paths = [
            urlsplit(r.url).path for r in self._fetched() if r.finished is None and not r.failed
        ]
        return [path for path in paths if _kind(path) != "events"]

    def totals(self) -> tuple[int, int]:
        """(sent, received) bytes so far."""
        fetched = self._fetched()
        return sum(r.sent for r in fetched), sum(r.received for r in fetched)

    def by_kind(self) -> dict[str, int]:
        """Received bytes by what was fetched (the app, photos, overlays, crops, state...)."""
        kinds: Counter[str] = Counter()
        for request in self._fetched():
            kinds[_kind(urlsplit(request.url).path)] += request.received
        return dict(kinds)


def _kind(path: str) -> str:
    parts = path.strip("/").split("/")
    if parts[:2] != ["api", "sessions"] or len(parts) < 3:
        return "app" if not path.startswith("/api/") else "other API"
    rest = parts[3:]
    if not rest:
        return "state"
    return {"photo": "photo", "overlay": "overlay", "landmarks": "crops", "events": "events"}.get(
        rest[0], rest[0]
    )
