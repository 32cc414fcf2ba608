"""One two-phone search as Locust plays it (``benchmarks/load.py``): both phones, their
open event streams, people's pauses. Everything the load benchmark knows of the session
API's requests and answers is in this module.

Each Locust user runs searches back to back. The starter creates the search and opens its
event stream; the joiner joins with the code and opens its own; both streams stay open to
the end. Like the app, each phone reads the state once its stream is open, then takes in
each event's data (``testbed.changes``, as ``frontend/src/changes.ts``), reading the state
again only when an event cannot be taken in (a change missed); it shows the state its own
PUT /taps answers with, draws the answer from that JSON and taps its own copy of its photo
(no overlay, no photo downloaded). Once its stream is live, each phone uploads its photo;
the starter marks the joiner and taps 6 landmarks one PUT at a time; for each, the joiner
waits until its state shows it, loads its crop ("find #n"), with ``--suggestions`` asks for
a suggested spot when the answer has a band for it (as the app does, once per answer), and
taps its own; both wait for the answer, read it, and the starter deletes the search, which
must end both streams with 'expired'.
"""

from __future__ import annotations

import itertools
import random
import time
from collections import Counter
from collections.abc import Callable, Iterator
from typing import Any, ClassVar

import gevent
from crowd import LANDMARKS, Crowd
from gevent.event import Event
from locust import User, constant, task
from locust.clients import HttpSession
from locust.exception import StopUser

from testbed.changes import take_in
from testbed.client import EventStream, server_timing

# A person's pauses, seconds, uniform in each range (divided by the speed-up): the joiner
# scans the code; each takes a photo; the starter picks and places a landmark; the joiner
# finds it from its crop; both read the answer. A search then lasts about 1.5 minutes.
PAUSES = {"join": (5, 15), "photo": (5, 15), "tap": (3, 8), "find": (5, 15), "read": (3, 10)}
CALL_SECONDS = 30.0  # any one call
STREAM_SILENCE_SECONDS = 45.0  # pings come every 15 s
WAIT_SECONDS = 30.0  # the longest a phone waits for what it expects to see
# Each call's time in the app, and its database statements' part of it (its Server-Timing:
# app;dur=<ms>, db;dur=<ms>), by name.
APP_MS: dict[str, list[float]] = {}
DATABASE_MS: dict[str, list[float]] = {}


class Phone:
    """One phone: its own HTTP session (a browser's own connections; Locust times and
    counts each call), its event stream read in a greenlet, the newest state it shows."""

    def __init__(self, user: Search, role: str, created: dict[str, Any]) -> None:
        self.user = user
        self.role = role
        self.http = user.session()
        self.token = str(created["token"])
        self.path = f"/api/sessions/{created['session_id']}"
        self.state: dict[str, Any] | None = None
        self.news = Event()  # set whenever the state shown changes
        self.live = Event()  # its stream announced this phone online
        self.expired = Event()
        self.sending = Event()  # a PUT /taps on its way: its answer will be the newest state
        self.sending.set()  # (set: none on its way)
        self.idle = Event()  # no state fetch on its way
        self.idle.set()
        self.ending = False  # the search is being deleted: nothing more to fetch
        self.reader = gevent.spawn(self._listen)

    def call(
        self, method: str, name: str, rest: str = "", expect: int = 200, **options: Any
    ) -> Any:
        """One call, timed and counted by Locust as ``name``; its JSON (or True) when it
        answered ``expect``, else None (counted as a failure)."""
        return call(
            self.http, method, self.path + rest, name, expect=expect, token=self.token, **options
        )

    def show(self, state: dict[str, Any] | None) -> None:
        """Keep the newest state (the app draws its answer from it)."""
        if state is None or (self.state is not None and state["version"] < self.state["version"]):
            return
        self.state = state
        self.news.set()

    def take_in(self, event: str, data: Any) -> None:
        """An event of its stream, taken in as the app does: shown, or the state read."""
        taken = take_in(self.state, event, data)
        if taken is None:
            self.fetch()
        elif taken is not self.state:
            self.show(taken)

    def fetch(self) -> None:
        if self.ending:
            return
        self.idle.clear()
        try:
            self.show(self.call("GET", "GET /api/sessions/{id}"))
        finally:
            self.idle.set()

    def settle(self) -> None:
        """No new fetches from now on; the one on its way (if any) done: the search can go."""
        self.ending = True
        self.idle.wait(CALL_SECONDS)

    def put_taps(self, body: dict[str, Any]) -> bool:
        self.sending.clear()
        try:
            state = self.call("PUT", "PUT /taps", "/taps", json=body)
        finally:
            self.sending.set()
        self.show(state)
        return state is not None

    def upload(self, photo: bytes) -> bool:
        """Its photo (the app taps its own copy meanwhile: nothing downloaded back)."""
        files = {"photo": ("photo.jpg", photo, "image/jpeg")}
        return self.call("PUT", "PUT /photo", "/photo", files=files) is not None

    def wait_until(self, shown: Callable[[dict[str, Any]], bool], what: str) -> bool:
        """Until the state shows ``shown``; False (a flow error) after WAIT_SECONDS."""
        deadline = time.monotonic() + WAIT_SECONDS
        while self.state is None or not shown(self.state):
            self.news.clear()
            if not self.news.wait(deadline - time.monotonic()):
                return self.user.flow_error(f"the {self.role} waited {WAIT_SECONDS:g} s for {what}")
        return True

    def wait_for(self, event: Event, what: str) -> bool:
        if not event.wait(WAIT_SECONDS):
            return self.user.flow_error(
                f"the {self.role}'s stream: no {what} in {WAIT_SECONDS:g} s"
            )
        return True

    def _listen(self) -> None:
        """The event stream, for the whole search: Locust times it to its first byte."""
        answer = self.http.get(
            f"{self.path}/events",
            name="GET /events (first byte)",
            params={"token": self.token},
            stream=True,
            timeout=(CALL_SECONDS, STREAM_SILENCE_SECONDS),
        )
        if answer.status_code != 200:
            return
        self.fetch()  # the phone shows the state at once (the QR code, the other's photo)
        try:
            for event in EventStream(answer.iter_content(chunk_size=None)):
                if event.type == "expired":
                    self.expired.set()
                    return
                online = event.data.get("role") == self.role and event.data.get("online")
                if event.type == "joined" and online:
                    self.live.set()
                self.sending.wait()  # the answer to its own PUT comes first
                self.take_in(event.type, event.data)
            self.user.flow_error("stream ended without 'expired'")
        except OSError as error:  # requests' and urllib3's errors, a read timeout among them
            self.user.flow_error(f"stream dropped ({type(error).__name__})")
        finally:
            answer.close()

    def close(self) -> None:
        self.reader.kill(block=True, timeout=5)
        self.http.close()


def call(
    http: HttpSession,
    method: str,
    path: str,
    name: str | None = None,
    *,
    expect: int = 200,
    token: str = "",
    **options: Any,
) -> Any:
    """``method path``, timed and counted by Locust as ``name`` (default ``method path``): its
    JSON (or True) when it answered ``expect``; else None, counted as a failure with its
    status and error code."""
    name = name or f"{method} {path}"
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    with http.request(
        method,
        path,
        name=name,
        catch_response=True,
        headers=headers,
        timeout=CALL_SECONDS,
        **options,
    ) as answer:
        if answer.status_code != expect:
            try:
                code = answer.json()["error"]["code"]
            except (ValueError, KeyError, TypeError):  # no answer, or not the app's
                code = answer.reason or repr(answer.error)
            answer.failure(f"{answer.status_code} {code}")
            return None
        answer.success()
        if header := answer.headers.get("server-timing"):
            parts = server_timing(header)
            APP_MS.setdefault(name, []).append(parts["app"])
            DATABASE_MS.setdefault(name, []).append(parts.get("db", 0.0))
        if answer.headers.get("content-type", "").startswith("application/json"):
            return answer.json()
        return True


def answered(state: dict[str, Any]) -> bool:
    """Whether the state has the answer its taps give: one, a refusal, or (more landmarks
    needed) none to wait for."""
    return (
        state.get("answer") is not None
        or state.get("answer_error") is not None
        or state["landmarks_needed"] > 0
    )


def banded(state: dict[str, Any], n: int) -> bool:
    """Whether the answer shows the joiner the band where the starter's landmark #n is."""
    answer = state.get("answer")
    bands = answer["in_photo"]["joiner"].get("bands", []) if answer else []
    return any(band["id"] == n for band in bands)


class Search(User):
    """A pair of friends running searches back to back, until ``stop_at``."""

    wait_time = constant(0)
    crowd: ClassVar[Crowd]
    authority: ClassVar[str | None] = None  # the certificate to trust
    speed: ClassVar[float] = 1.0  # people this many times quicker
    stop_at: ClassVar[float] = float("inf")  # time.monotonic(): no search starts after
    seed: ClassVar[int] = 0
    suggestions: ClassVar[bool] = False  # ask for a suggested spot, as the app does
    counts: ClassVar[Counter[str]] = Counter()  # searches started, completed
    durations: ClassVar[list[float]] = []  # of completed searches, s
    numbers: ClassVar[Iterator[int]] = itertools.count()

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.number = next(Search.numbers)
        self.searches = 0

    def session(self) -> HttpSession:
        """A new HTTP session (a phone's own connections) trusting ``authority``; the
        environment's certificate bundle and proxies (requests reads them) do not apply."""
        http = HttpSession(self.host, self.environment.events.request, self)
        http.trust_env = False
        http.verify = self.authority or True
        return http

    def flow_error(self, what: str) -> bool:
        """Something a phone expected did not happen: a failure in Locust's table."""
        self.environment.events.request.fire(
            request_type="FLOW",
            name=what,
            response_time=0,
            response_length=0,
            exception=RuntimeError(what),
        )
        return False

    def pause(self, rng: random.Random, step: str) -> None:
        gevent.sleep(rng.uniform(*PAUSES[step]) / self.speed)

    @task
    def search(self) -> None:
        if time.monotonic() >= self.stop_at:
            raise StopUser
        rng = random.Random(f"{self.seed}-{self.number}-{self.searches}")
        self.searches += 1
        Search.counts["started"] += 1
        started = time.monotonic()
        starter_taps, joiner_taps, mark = self.crowd.taps(rng)
        lobby = self.session()
        created = call(lobby, "POST", "/api/sessions", expect=201)
        if created is None:
            return
        starter = Phone(self, "starter", created)
        phones = [starter]
        try:
            self.pause(rng, "join")
            joined = call(lobby, "POST", "/api/sessions/join", json={"code": created["join_code"]})
            if joined is None:
                return
            joiner = Phone(self, "joiner", joined)
            phones.append(joiner)
            starter_side = gevent.spawn(self.starter_side, starter, starter_taps, mark, rng)
            joiner_side = gevent.spawn(self.joiner_side, joiner, joiner_taps, rng)
            starter_side.join()
            joiner_side.join()
            answered = bool(starter_side.value and joiner_side.value) and all(
                phone.wait_until(lambda state: state.get("answer") is not None, "the answer")
                for phone in phones
            )
            if not answered:
                return
            self.pause(rng, "read")
            for phone in phones:
                phone.settle()
            if starter.call("DELETE", "DELETE /api/sessions/{id}", expect=204) is None:
                return
            if all(phone.wait_for(phone.expired, "'expired'") for phone in phones):
                Search.counts["completed"] += 1
                Search.durations.append(time.monotonic() - started)
        finally:
            if not starter.expired.is_set():  # a failed search: deleted all the same
                headers = {"Authorization": f"Bearer {starter.token}"}
                lobby.delete(
                    starter.path, headers=headers, name="DELETE (clean-up after a failure)"
                )
            for phone in phones:
                phone.close()
            lobby.close()

    def starter_side(
        self, phone: Phone, taps: list[dict[str, float]], mark: dict[str, float], rng: random.Random
    ) -> bool:
        if not self.photo_taken(phone, self.crowd.photos[0], rng):
            return False
        for n in range(1, LANDMARKS + 1):
            self.pause(rng, "tap")
            if not phone.put_taps({"landmarks": taps[:n], "friend": mark}):
                return False
        return True

    def joiner_side(self, phone: Phone, taps: list[dict[str, float]], rng: random.Random) -> bool:
        if not self.photo_taken(phone, self.crowd.photos[1], rng):
            return False
        for n in range(1, LANDMARKS + 1):

            def tapped(state: dict[str, Any], n: int = n) -> bool:
                starter = state["taps"].get("starter")
                return starter is not None and any(t["id"] == n for t in starter["landmarks"])

            if not phone.wait_until(tapped, f"the starter's landmark #{n}") or not (
                phone.wait_until(answered, f"the answer with the starter's landmark #{n}")
            ):
                return False
            assert phone.state is not None
            seen = next(t for t in phone.state["taps"]["starter"]["landmarks"] if t["id"] == n)
            crop = f"/landmarks/starter/{n}/crop"
            query = {"token": phone.token, "v": f"{seen['x']},{seen['y']}"}
            if phone.call("GET", "GET /landmarks/starter/{n}/crop", crop, params=query) is None:
                return False
            suggestion = f"/landmarks/joiner/{n}/suggestion"
            asked = self.suggestions and banded(phone.state, n)
            if (
                asked
                and phone.call("GET", "GET /landmarks/joiner/{n}/suggestion", suggestion) is None
            ):
                return False
            self.pause(rng, "find")
            if not phone.put_taps({"landmarks": taps[:n]}):
                return False
        return True

    def photo_taken(self, phone: Phone, photo: bytes, rng: random.Random) -> bool:
        """Once its stream is live: a person's pause for the photo, then its upload."""
        if not phone.wait_for(phone.live, "own 'joined'"):
            return False
        self.pause(rng, "photo")
        return phone.upload(photo)
