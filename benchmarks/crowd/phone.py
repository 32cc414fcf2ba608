"""One phone: its own HTTP client, its calls, its event stream and the state it shows,
as the phone app does (``alreadyShown``, one state fetch in flight, held changes)."""

from __future__ import annotations

import asyncio
import json
import ssl
import time
from collections import Counter
from collections.abc import Callable
from contextlib import suppress
from dataclasses import dataclass
from typing import Any

import httpx2

from .recorder import EVENTS, OVERLAY, STATE, TAPS, Recorder, error_kind

PHONE_CONNECTIONS = 6  # a browser's limit per host over HTTP/1.1
KEEPALIVE_SECONDS = 4.0  # below uvicorn's 5 s
MAX_REFETCHES = 1000  # per burst of events: a bound for one phone's refetch loop

REQUEST_SECONDS = 30.0  # any one call: connect, pool wait, read
STREAM_READ_SECONDS = 45.0  # silence on an event stream (pings come every 15 s)
WAIT_SECONDS = 30.0  # the longest a phone waits for something it expects to see
CLEANUP_SECONDS = 5.0  # deleting a failed session, not measured


def http_client(base_url: str, tls: ssl.SSLContext) -> httpx2.AsyncClient:
    """A phone's own client. One client shared by all phones would hold hundreds of
    connections, and httpcore's pool does work quadratic in that number per request."""
    # Idle connections closed before uvicorn closes them (after 5 s): a request sent on
    # a connection the server is closing fails. A browser sends it again on a new one;
    # httpx does not, so it must not reuse a connection that old.
    limits = httpx2.Limits(
        max_connections=PHONE_CONNECTIONS,
        max_keepalive_connections=PHONE_CONNECTIONS,
        keepalive_expiry=KEEPALIVE_SECONDS,
    )
    return httpx2.AsyncClient(base_url=base_url, limits=limits, timeout=REQUEST_SECONDS, verify=tls)


@dataclass(frozen=True)
class Change:
    """What an event said changed, and the session version it made (None: no version)."""

    type: str
    version: int | None


def already_shown(change: Change, shown: dict[str, Any] | None) -> bool:
    """Whether the state shown holds ``change`` already: the phone app's ``alreadyShown``
    (frontend/src/reconnect.ts), which spares a phone fetching its own changes."""
    if change.version is None or shown is None:
        return False
    if change.type == "answer":
        answered = shown.get("answer") is not None or shown.get("answer_error") is not None
        return shown["version"] > change.version or (
            shown["version"] == change.version and answered
        )
    return bool(shown["version"] >= change.version)


class Phone:
    """One participant: its own HTTP client (keep-alive, a browser's few connections), its
    calls, its event stream, the state it shows."""

    def __init__(self, rec: Recorder, http: httpx2.AsyncClient, role: str) -> None:
        self.rec = rec
        self.role = role
        self.http = http
        self.session_id = ""
        self.token = ""
        self.auth: dict[str, str] = {}
        self.state: dict[str, Any] | None = None
        self.shown = asyncio.Condition()
        self.events: Counter[str] = Counter()
        self.live = asyncio.Event()  # its stream has announced this phone (own 'joined')
        self.expired = asyncio.Event()
        self.stream: asyncio.Task[None] | None = None
        self.fetching: asyncio.Task[None] | None = None
        self.again = False
        self.ending = False  # no new state fetches: the session is being deleted
        self.fetches = 0
        self.sending = False  # a PUT /taps on its way: its reply will be the newest state
        self.held: list[Change] = []  # changes told meanwhile, judged when the reply is in
        self.drawing: asyncio.Task[None] | None = None  # the overlay <img> loading
        self.drawn: int | None = None  # the answer version of the overlay last loaded

    def enter(self, session_id: str, token: str) -> None:
        self.session_id, self.token = session_id, token
        self.auth = {"Authorization": f"Bearer {token}"}

    def url(self, rest: str = "") -> str:
        return f"/api/sessions/{self.session_id}{rest}"

    async def call(
        self, endpoint: str, method: str, url: str, *, expect: int = 200, **options: Any
    ) -> httpx2.Response | None:
        """One request, timed and recorded; None unless it answered ``expect``."""
        rec = self.rec
        rec.requests_in_flight += 1
        started = time.perf_counter()
        try:
            response = await self.http.request(method, url, headers=self.auth, **options)
        except httpx2.TimeoutException:
            rec.failed(endpoint, "timeout")
            return None
        except httpx2.TransportError as error:
            rec.failed(endpoint, type(error).__name__)
            return None
        finally:
            rec.requests_in_flight -= 1
        if response.status_code != expect:
            rec.failed(endpoint, error_kind(response))
            return None
        rec.ok(endpoint, (time.perf_counter() - started) * 1000, response)
        return response

    # The state, fetched after every event that tells something it does not show (the phone
    # app's alreadyShown); at most one fetch in flight, one more after it when events came
    # meanwhile (its Refetcher); changes told while its own PUT is on its way are judged
    # when the reply is in (its held changes).

    def changed(self, *changes: Change) -> None:
        if self.sending:
            self.held.extend(changes)
        elif any(not already_shown(change, self.state) for change in changes):
            self.refetch()

    async def put_taps(self, body: dict[str, Any]) -> bool:
        """Its taps, as the app's TapSaver sends them; the reply is shown."""
        self.sending = True
        try:
            answered = await self.call(TAPS, "PUT", self.url("/taps"), json=body)
        finally:
            self.sending = False
        if answered is not None:
            await self.show(answered.json())
        held, self.held = self.held, []
        self.changed(*held)
        return answered is not None

    def refetch(self) -> None:
        if self.ending:
            return
        if self.fetching is not None and not self.fetching.done():
            self.again = True
            return
        self.fetching = asyncio.create_task(self._fetch_until_current())

    async def _fetch_until_current(self) -> None:
        for _ in range(MAX_REFETCHES):
            self.again = False
            self.fetches += 1
            response = await self.call(STATE, "GET", self.url())
            if response is not None:
                await self.show(response.json())
            if not self.again or self.ending:
                return

    async def settled(self) -> None:
        """Until the state fetch in flight (if any) is done; no new ones after this."""
        self.ending = True
        for task in (self.fetching, self.drawing):
            if task is not None:
                with suppress(TimeoutError):
                    await asyncio.wait_for(asyncio.shield(task), REQUEST_SECONDS)

    async def show(self, state: dict[str, Any]) -> None:
        """Keep the newest state (an older one that arrives late is dropped); an answer not
        drawn yet loads its overlay (the app's <img>, one at a time, the newest)."""
        if self.state is None or state["version"] >= self.state["version"]:
            self.state = state
            async with self.shown:
                self.shown.notify_all()
            new_answer = state.get("answer") is not None and state["answer_version"] != self.drawn
            if new_answer and (self.drawing is None or self.drawing.done()):
                self.drawing = asyncio.create_task(self._draw())

    async def _draw(self) -> None:
        while not self.ending and self.state is not None and self.state.get("answer"):
            version = self.state["answer_version"]
            if version == self.drawn:
                return
            self.drawn = version
            params = {"token": self.token, "v": str(version)}
            await self.call(OVERLAY, "GET", self.url(f"/overlay/{self.role}"), params=params)

    async def wait_for(self, seen: Callable[[dict[str, Any]], bool], what: str) -> bool:
        """Until the state shows ``seen``; False (and counted) after WAIT_SECONDS."""

        def shown() -> bool:
            return self.state is not None and seen(self.state)

        async with self.shown:
            try:
                await asyncio.wait_for(self.shown.wait_for(shown), WAIT_SECONDS)
            except TimeoutError:
                self.rec.flow(f"the {self.role} waited {WAIT_SECONDS:g} s for {what}")
                return False
        return True

    async def wait_event(self, event: asyncio.Event, what: str) -> bool:
        try:
            await asyncio.wait_for(event.wait(), WAIT_SECONDS)
        except TimeoutError:
            self.rec.flow(f"the {self.role}'s stream: no {what} in {WAIT_SECONDS:g} s")
            return False
        return True

    # The event stream, open for the whole session.

    def listen(self) -> None:
        self.stream = asyncio.create_task(self._listen())

    async def _listen(self) -> None:
        timeout = httpx2.Timeout(REQUEST_SECONDS, read=STREAM_READ_SECONDS)
        started = time.perf_counter()
        opened = False
        try:
            async with self.http.stream(
                "GET", self.url("/events"), params={"token": self.token}, timeout=timeout
            ) as response:
                if response.status_code != 200:
                    await response.aread()
                    self.rec.failed(EVENTS, error_kind(response))
                    return
                self.rec.ok(EVENTS, (time.perf_counter() - started) * 1000, response)
                self.rec.streams_opened += 1
                self.rec.streams_open += 1
                opened = True
                await self._read(response)
        except httpx2.TimeoutException:
            if opened:
                self.rec.flow("stream silent too long (read timeout)")
            else:
                self.rec.failed(EVENTS, "timeout")
        except httpx2.TransportError as error:
            if opened:
                self.rec.flow(f"stream dropped ({type(error).__name__})")
            else:
                self.rec.failed(EVENTS, type(error).__name__)
        finally:
            if opened:
                self.rec.streams_open -= 1

    async def _read(self, response: httpx2.Response) -> None:
        kind = None
        async for line in response.aiter_lines():
            if line.startswith("event: "):
                kind = line[7:]
                self.events[kind] += 1
                self.rec.events[kind] += 1
                if kind == "expired":
                    self.expired.set()
                    return
            elif line.startswith("data: ") and kind is not None:
                data = json.loads(line[6:])
                if kind == "joined" and data.get("role") == self.role and data.get("online"):
                    self.live.set()
                version = data.get("version")
                self.changed(Change(kind, version if isinstance(version, int) else None))
                kind = None
        self.rec.flow("stream ended without 'expired'")

    async def discard(self) -> None:
        """Delete its session, not measured: the clean-up after a failure (it may have been
        deleted already, by a DELETE cut off by the time limit)."""
        self.ending = True
        with suppress(httpx2.HTTPError):
            await self.http.delete(self.url(), headers=self.auth, timeout=CLEANUP_SECONDS)

    async def close(self) -> None:
        """Stop its tasks (a failed session: the stream may still be open), close its client."""
        for task in (self.stream, self.fetching, self.drawing):
            if task is not None and not task.done():
                task.cancel()
                with suppress(asyncio.CancelledError, Exception):
                    await task
        await self.http.aclose()
