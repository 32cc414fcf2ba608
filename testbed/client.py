"""One phone's side of the session API, for the tests, the benchmarks and the load tool.

:class:`Phone` makes a phone's HTTP calls over any ``httpx2.Client``: Starlette's
in-process ``TestClient``, or a client of a live server (a replica, or nginx in front of
them). :class:`EventStream` reads a phone's event stream from the bytes of any HTTP
client's streamed answer (httpx2's here, requests' in Locust's phones,
``benchmarks/searches.py``), and :class:`Listener` follows one in a thread. What a phone
shows after each event is :mod:`testbed.changes`. :func:`server_timing` reads the app's own
time from an answer.
"""

from __future__ import annotations

import json
import mimetypes
import threading
import time
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx2
from sseclient import SSEClient

# The server's keep-alive: a comment line (backend/eventstream/stream.py).
PING = b": ping\n"
SECONDS = 30.0  # a call's timeout


@dataclass(frozen=True)
class Event:
    """One event of a session's stream: its type, id (None: not stored, so not resumable)
    and JSON data."""

    type: str
    id: int | None
    data: Any


class EventStream:
    """The events of a stream's byte chunks, as they arrive.

    sseclient-py parses them (any HTTP client's chunks, as a browser's EventSource does).
    It drops comments, as the standard says a client does; the server's pings are comments,
    so they are counted here from the bytes (``pings``): a test checks that nothing but
    the events themselves pushed them through nginx.
    """

    def __init__(self, chunks: Iterable[bytes]) -> None:
        self.chunks = chunks
        self.pings = 0

    def __iter__(self) -> Iterator[Event]:
        for event in SSEClient(self._counted()).events():
            number = None if event.id is None else int(event.id)
            yield Event(event.event, number, json.loads(event.data))

    def _counted(self) -> Iterator[bytes]:
        tail = b""  # shorter than a ping: a ping split between chunks is counted once
        for chunk in self.chunks:
            seen = tail + chunk
            self.pings += seen.count(PING)
            tail = seen[-(len(PING) - 1) :]
            yield chunk


def frame(text: str) -> Event:
    """The event one frame of the stream's text holds (as the server writes it)."""
    return next(iter(EventStream([text.encode()])))


@dataclass(frozen=True)
class Phone:
    """One participant's calls: ``client`` is the HTTP client (its base URL the server's),
    ``role`` the participant's ("starter" or "joiner")."""

    client: httpx2.Client
    session_id: str
    token: str
    role: str = ""

    @property
    def auth(self) -> dict[str, str]:
        return {"Authorization": f"Bearer {self.token}"}

    def url(self, rest: str = "") -> str:
        return f"/api/sessions/{self.session_id}{rest}"

    def call(
        self, method: str, rest: str = "", headers: dict[str, str] | None = None, **options: Any
    ) -> httpx2.Response:
        """``method`` on the session's ``rest`` with the phone's token: the answer as it is."""
        headers = self.auth | (headers or {})
        return self.client.request(method, self.url(rest), headers=headers, **options)

    def ok(self, method: str, rest: str = "", expect: int = 200, **options: Any) -> httpx2.Response:
        """The same, failing unless the answer's status is ``expect``."""
        answer = self.call(method, rest, **options)
        assert answer.status_code == expect, f"{method} {rest}: {answer.status_code} {answer.text}"
        return answer

    def state(self) -> dict[str, Any]:
        return dict(self.ok("GET").json())

    def upload(
        self,
        photo: bytes | Path,
        name: str = "photo.jpg",
        kind: str | None = None,
        data: dict[str, Any] | None = None,
    ) -> httpx2.Response:
        """PUT a photo: bytes, sent as ``name`` of type ``kind`` (JPEG unless told: what a
        phone's camera sends, whatever the bytes), or a file, sent under its own name and
        its name's type; ``data``: the form's other fields (the lens, sensor readings)."""
        return self.call("PUT", "/photo", files=self._form(photo, name, kind), data=data)

    @staticmethod
    def _form(
        photo: bytes | Path, name: str = "photo.jpg", kind: str | None = None
    ) -> dict[str, tuple[str, bytes, str]]:
        if isinstance(photo, Path):
            name, kind, photo = photo.name, mimetypes.guess_type(photo.name)[0], photo.read_bytes()
        return {"photo": (name, photo, kind or "image/jpeg")}

    def uploaded(self, photo: bytes | Path) -> dict[str, Any]:
        """PUT a photo, failing unless stored: what the server stored of it."""
        return dict(self.ok("PUT", "/photo", files=self._form(photo)).json())

    def tap(self, **taps: Any) -> httpx2.Response:
        """PUT these taps; a ``friend`` given as ``(x, y)`` (a pair, or an array's) is sent
        as ``{"x", "y"}``; landmarks as the API takes them (:func:`numbered`)."""
        return self.call("PUT", "/taps", json=self._taps(taps))

    def tapped(self, **taps: Any) -> dict[str, Any]:
        """PUT these taps, failing unless taken: the state the server answers with."""
        return dict(self.ok("PUT", "/taps", json=self._taps(taps)).json())

    @staticmethod
    def _taps(taps: dict[str, Any]) -> dict[str, Any]:
        friend = taps.get("friend")
        if friend is not None and not isinstance(friend, dict):
            x, y = friend
            return taps | {"friend": {"x": float(x), "y": float(y)}}
        return taps

    def listen(self, last_event_id: int | None = None) -> Listener:
        """Its event stream, followed from now on in a thread (from after
        ``last_event_id``, as a reconnecting EventSource asks)."""
        listener = Listener(str(self.client.base_url).rstrip("/") + self.url(), self.token)
        if last_event_id is not None:
            listener.headers["Last-Event-ID"] = str(last_event_id)
        listener.start()
        return listener


def server_timing(header: str) -> dict[str, float]:
    """The parts of a ``Server-Timing`` header, ms by name (``app;dur=1.2, db;dur=0.4``:
    the app's time and its database statements' share, backend/middleware.py)."""
    parts = {}
    for entry in header.split(","):
        name, *parameters = (part.strip() for part in entry.split(";"))
        for parameter in parameters:
            key, _, value = parameter.partition("=")
            if key == "dur":
                parts[name] = float(value)
    return parts


def live(base: str) -> httpx2.Client:
    """A client of the live server at ``base``: a new connection for each call (none is
    kept alive to a replica that may be stopped between calls)."""
    limits = httpx2.Limits(max_keepalive_connections=0)
    return httpx2.Client(base_url=base, timeout=SECONDS, limits=limits)


def numbered(points: Iterable[Iterable[float]]) -> list[dict[str, Any]]:
    """Landmark taps as the API takes them: ``points`` ((N, 2) px, e.g. an array's rows)
    numbered 1 to N in their order."""
    return [{"id": i, "x": float(x), "y": float(y)} for i, (x, y) in enumerate(points, 1)]


def start(client: httpx2.Client, photo: bytes | Path | None = None) -> tuple[Phone, str]:
    """A new search started through ``client``, with the starter's ``photo`` when given:
    the starter's calls, and the join code another phone joins with (by the API, or by the
    app's link ``/join/{code}``)."""
    created = client.post("/api/sessions")
    assert created.status_code == 201, created.text
    body = created.json()
    starter = Phone(client, body["session_id"], body["token"], "starter")
    if photo is not None:
        starter.uploaded(photo)
    return starter, str(body["join_code"])


def pair(starter: httpx2.Client, joiner: httpx2.Client | None = None) -> tuple[Phone, Phone]:
    """A new search: the starter starts it through one client, the joiner joins with the
    code through the other (the same one by default)."""
    joiner = joiner or starter
    first, code = start(starter)
    joined = joiner.post("/api/sessions/join", json={"code": code})
    assert joined.status_code == 200, joined.text
    return first, Phone(joiner, first.session_id, joined.json()["token"], "joiner")


class Listener(threading.Thread):
    """A phone's event stream over HTTP, collected in the background until 'expired'."""

    def __init__(self, session_url: str, token: str) -> None:
        super().__init__(daemon=True)
        self.url = f"{session_url}/events"
        self.token = token
        self.headers: dict[str, str] = {}
        self.events: list[Event] = []
        self.stream = EventStream(())
        self.ended = threading.Event()
        self.dropped = False

    @property
    def types(self) -> list[str]:
        return [event.type for event in self.events]

    @property
    def ids(self) -> list[int]:
        return [event.id for event in self.events if event.id is not None]

    @property
    def pings(self) -> int:
        return self.stream.pings

    def run(self) -> None:
        try:
            with httpx2.stream(
                "GET", self.url, params={"token": self.token}, headers=self.headers, timeout=30
            ) as answer:
                assert answer.status_code == 200
                assert answer.headers["content-type"].startswith("text/event-stream")
                self.stream = EventStream(answer.iter_bytes())
                for event in self.stream:
                    self.events.append(event)
                    if event.type == "expired":
                        break
        except httpx2.TransportError:
            self.dropped = True  # the server went away (a phone's EventSource reconnects)
        self.ended.set()

    def count(self, type_: str, **data: Any) -> int:
        """How many ``type_`` events have arrived whose data has these items."""
        return sum(
            1 for event in self.events if event.type == type_ and data.items() <= event.data.items()
        )

    def wait_for(self, type_: str, count: int = 1, seconds: float = 15, **data: Any) -> None:
        """Until ``count`` such events have arrived; fails after ``seconds``."""
        deadline = time.monotonic() + seconds
        while self.count(type_, **data) < count:
            assert time.monotonic() < deadline, (
                f"no {type_} {data} event in {seconds} s; got {self.types}"
            )
            time.sleep(0.02)

    def wait_for_id(self, event_id: int, seconds: float = 15) -> None:
        """Until the event numbered ``event_id`` (or a later one) has arrived."""
        deadline = time.monotonic() + seconds
        while not self.ids or self.ids[-1] < event_id:
            assert time.monotonic() < deadline, f"no event {event_id} in {seconds} s: {self.ids}"
            time.sleep(0.02)


def follow(starter: Phone, joiner: Phone, seconds: float = 15) -> tuple[Listener, Listener]:
    """Both phones' event streams. The starter's is open first (its own presence came
    back), so the joiner coming online is news to it: within ``seconds``, from wherever the
    joiner's stream is."""
    starter_events = starter.listen()
    starter_events.wait_for("joined", role="starter", online=True)
    joiner_events = joiner.listen()
    joiner_events.wait_for("joined", role="joiner", online=True)
    starter_events.wait_for("joined", role="joiner", online=True, seconds=seconds)
    return starter_events, joiner_events
