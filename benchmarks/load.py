"""Buddy Search load benchmark: many two-phone sessions at once, event streams open, one run.

One real uvicorn (``backend.main:app``; one worker unless ``--workers``; a new SQLite
database in a temporary folder unless ``--database postgresql``), started by this script on
a free loopback port and stopped at the end. An asyncio driver plays both phones of every
session as the phone app does, each phone with its own ``httpx.AsyncClient`` (keep-alive):

1. Costs: each kind of call alone, one at a time, with the server's CPU read from /proc
   around it: what each call costs the server.
2. Quiet server: a few whole sessions one at a time: each call's time without queueing,
   the calls a session makes and the server CPU it costs.
3. Idle streams: N sessions paired, both event streams open, nobody tapping: what the open
   streams cost by themselves (each re-reads the event table every poll interval).
4. Load: N slots, each running whole sessions back to back until ``--duration`` s have
   passed (or ``--sessions`` have started): the seeker creates the session and opens its
   event stream for the whole session; the buddy joins with the code and opens its own;
   both upload a photo; the seeker marks the buddy and taps 6 landmarks one PUT at a time;
   the buddy finds each one (the crop of the seeker's landmark #n) and taps it; each phone
   fetches the state after every event (at most one fetch in flight per phone); the buddy
   fetches its overlay once the answer is there; the seeker deletes the session, which
   ends both streams with ``expired``. Human-like pauses (random, seeded) between steps.

Run from the repository root:

    .venv/bin/python benchmarks/load.py [--concurrency N] [--duration S] [--sessions K]
        [--speed X] [--workers W] [--database sqlite|postgresql]
        [--event-poll-seconds S] [--out PATH]                          (``make bench-load``)

The report is printed and written as Markdown to ``docs/load-benchmark.md``.
"""

from __future__ import annotations

import argparse
import asyncio
import importlib.util
import json
import math
import os
import platform
import re
import shlex
import sqlite3
import ssl
import subprocess
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Awaitable, Callable, Iterator, Sequence
from contextlib import closing, contextmanager, suppress
from dataclasses import dataclass, field
from datetime import datetime
from functools import partial
from importlib.metadata import version
from pathlib import Path
from typing import Any

import anyio.to_thread
import cv2
import httpx
import numpy as np
from report import (
    CLOCK_TICKS,
    machine_cpu_seconds,
    markdown_table,
    percent,
    uvicorn_stack,
    verdict,
)

from backend.loopback import Server, serve
from backend.settings import Settings
from backend.storage.database import connect
from shared_solver.scenes import Scene, tap, temple_scene

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = ROOT / "docs" / "load-benchmark.md"
TEMPLE = ROOT / "tests" / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")  # the seeker's photo, the buddy's

# --- what is measured, and the targets ---------------------------------------------------

DEFAULT_CONCURRENCY = 200
DEFAULT_DURATION = 120.0
DEFAULT_RAMP = 30.0  # slot i starts its first session at i / N of this: no thundering herd
DEFAULT_IDLE_SECONDS = 10.0
# A person's pauses, seconds, uniform in each range (``--speed`` divides them): the buddy
# scans the QR code or types the code; each takes a photo; the seeker picks a landmark and
# places it with the loupe; the buddy finds the seeker's landmark #n in their own photo from
# its crop; both read the answer before "Delete now". A session then lasts about 1.5 min.
PAUSES = {
    "join": (5.0, 15.0),
    "photo": (5.0, 15.0),
    "tap": (3.0, 8.0),
    "find": (5.0, 15.0),
    "read": (3.0, 10.0),
}
DEFAULT_SPEED = 1.0
QUIET_SPEED = 20.0  # the quiet phase: one session at a time, pauses are only waiting
SOLO_SESSIONS = 5
COST_CALLS = 20  # of each kind, for the server CPU per call
DRAIN_SECONDS = 180.0  # sessions still running at the end of the duration get this long
SETTLE_SECONDS = 2.0  # after the idle streams are open, before their CPU is measured
PAIRING_CONCURRENCY = 20  # sessions paired at once for the idle phase
OVERALL_SLACK_SECONDS = 600.0  # the whole measurement: idle + duration + this, at most
MAX_SESSIONS_PER_SLOT = 100_000  # a bound, far above what a slot can run
PHONE_CONNECTIONS = 6  # a browser's limit per host over HTTP/1.1
KEEPALIVE_SECONDS = 4.0  # below uvicorn's 5 s
MAX_REFETCHES = 1000  # per burst of events: a bound for one phone's refetch loop

LANDMARKS = 6
LATENCY_TARGET_MS = 500.0  # p99 of every call but the photo upload
SEED = 20261121

REQUEST_SECONDS = 30.0  # any one call: connect, pool wait, read
STREAM_READ_SECONDS = 45.0  # silence on an event stream (pings come every 15 s)
WAIT_SECONDS = 30.0  # the longest a phone waits for something it expects to see
CLEANUP_SECONDS = 5.0  # deleting a failed session, not measured
SAMPLE_SECONDS = 1.0
LAG_PROBE_SECONDS = 0.05

PHOTO_SIZE = (1600, 1200)  # a phone's shrunk photo: the temple views upscaled 2.5x
PHOTO_QUALITY = 92
PHOTO_NOISE_SIGMA = 6.0  # grey levels: sensor noise, so the JPEG weighs what a photo does
TAP_SIGMA_PX = 2.0  # a finger's noise on the 1600x1200 photo
SCENES = 64  # temple scenes drawn up front; each session adds its own tap noise

CREATE = "POST /api/sessions"
JOIN = "POST /api/sessions/join"
EVENTS = "GET /events (first byte)"
PHOTO = "PUT /photo"
STORED = "GET /photo/{own role}"
TAPS = "PUT /taps"
STATE = "GET /api/sessions/{id}"
CROP = "GET /landmarks/seeker/{n}/crop"
OVERLAY = "GET /overlay/{own role}"
DELETE = "DELETE /api/sessions/{id}"
ENDPOINTS = (CREATE, JOIN, EVENTS, PHOTO, STORED, TAPS, STATE, CROP, OVERLAY, DELETE)
EXEMPT = {PHOTO}  # not held to the p99 target
EXPECTED_EVENTS = ("joined", "photo", "taps", "result", "expired")  # on both streams
STREAMS_HELD = 0.9  # of the 2N streams open (steady median), for the concurrency target

CORES = os.cpu_count() or 1
BUSY_MACHINE_CORES = 0.1  # other programs using more than this spoil the comparison


# --- CPU and memory of the server (/proc, so no psutil) -----------------------------------


def process_tree(pid: int) -> list[int]:
    """``pid`` and its descendants (uvicorn's workers, with ``--workers``)."""
    parents: dict[int, int] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        with suppress(OSError, IndexError, ValueError):
            parents[int(stat.parent.name)] = int(stat.read_text().rsplit(")", 1)[1].split()[1])
    tree, frontier = [pid], [pid]
    while frontier:
        children = [child for child, parent in parents.items() if parent in frontier]
        tree += children
        frontier = children
    return tree


def process_cpu_seconds(pid: int) -> float:
    """utime + stime of every thread of ``pid`` (fields 14 and 15 of /proc/<pid>/stat)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS


def peak_memory_mb(pid: int) -> float:
    """VmHWM of ``pid``: the most resident memory it has had, MB."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return 0.0
    found = re.search(r"^VmHWM:\s+(\d+) kB", status, re.M)
    return int(found.group(1)) / 1024 if found else 0.0


@dataclass(frozen=True)
class CpuSnapshot:
    """Cumulative CPU seconds at one instant: the server (all its processes), this process,
    the machine."""

    at: float  # time.monotonic()
    server: float
    client: float
    machine_busy: float
    machine_total: float


@dataclass(frozen=True)
class CpuUse:
    """CPU spent between two snapshots, in cores (CPU seconds per wall second)."""

    seconds: float
    server: float
    client: float
    machine: float  # share of all cores busy, 0..1

    @property
    def others(self) -> float:
        """Cores kept busy by neither side: other programs on the machine, the kernel."""
        return max(self.machine * CORES - self.server - self.client, 0.0)

    @staticmethod
    def between(first: CpuSnapshot, last: CpuSnapshot) -> CpuUse:
        wall = max(last.at - first.at, 1e-9)
        total = max(last.machine_total - first.machine_total, 1e-9)
        return CpuUse(
            wall,
            (last.server - first.server) / wall,
            (last.client - first.client) / wall,
            (last.machine_busy - first.machine_busy) / total,
        )


def cpu_snapshot(server_pids: Sequence[int]) -> CpuSnapshot:
    busy, total = machine_cpu_seconds()
    server = sum(process_cpu_seconds(pid) for pid in server_pids)
    return CpuSnapshot(time.monotonic(), server, time.process_time(), busy, total)


# --- what the phones send ------------------------------------------------------------------


def phone_photo(name: str, rng: np.random.Generator) -> bytes:
    """A temple view upscaled to 1600x1200 (bicubic) with Gaussian sensor-like noise, as
    the JPEG a phone sends after shrinking its photo: real edges, a realistic weight."""
    image = cv2.imread(str(TEMPLE / f"{name}.png"), cv2.IMREAD_COLOR)
    if image is None:
        raise FileNotFoundError(TEMPLE / f"{name}.png")
    large = cv2.resize(image, PHOTO_SIZE, interpolation=cv2.INTER_CUBIC).astype(np.float32)
    noisy = np.clip(large + rng.normal(0.0, PHOTO_NOISE_SIGMA, large.shape), 0, 255)
    ok, data = cv2.imencode(
        ".jpg", noisy.astype(np.uint8), [cv2.IMWRITE_JPEG_QUALITY, PHOTO_QUALITY]
    )
    if not ok:
        raise RuntimeError("OpenCV could not encode the photo")
    return bytes(data.tobytes())


def temple_scenes(rng: np.random.Generator) -> list[Scene]:
    """Landmarks drawn on the temple, seen by the calibrated cameras of the two photos."""
    parameters = TEMPLE / "templeSR_par.txt"
    return [temple_scene(parameters, *PAIR, LANDMARKS, rng) for _ in range(SCENES)]


@dataclass(frozen=True)
class SessionTaps:
    """What both people tap in one session, in the 1600x1200 photos' pixels."""

    seeker: list[dict[str, float]]  # landmarks #1..#6
    buddy: list[dict[str, float]]
    buddy_mark: list[float]  # e1: the buddy, in the seeker's photo


def session_taps(scene: Scene, rng: np.random.Generator) -> SessionTaps:
    scale = PHOTO_SIZE[0] / scene.image_size1[0]  # the temple views are 640x480
    noisy = tap(scene, TAP_SIGMA_PX / scale, rng)

    def marks(points: np.ndarray) -> list[dict[str, float]]:
        inside = np.clip(points * scale, 0, PHOTO_SIZE)
        return [
            {"id": n, "x": round(float(x), 1), "y": round(float(y), 1)}
            for n, (x, y) in enumerate(inside, start=1)
        ]

    buddy_mark = np.clip(noisy.epipole1 * scale, 0, PHOTO_SIZE)
    return SessionTaps(
        marks(noisy.landmarks1), marks(noisy.landmarks2), [round(float(v), 1) for v in buddy_mark]
    )


# --- what was measured ---------------------------------------------------------------------


@dataclass
class Calls:
    """One endpoint: client latency and server time (Server-Timing) of each successful call,
    and the failed calls by kind."""

    latency_ms: list[float] = field(default_factory=list)
    server_ms: list[float] = field(default_factory=list)
    errors: Counter[str] = field(default_factory=Counter)


@dataclass(frozen=True)
class Sample:
    """The state of the run at one instant (every SAMPLE_SECONDS)."""

    cpu: CpuSnapshot
    sessions: int
    streams: int
    requests: int


@dataclass
class Recorder:
    """Everything one phase measured."""

    calls: dict[str, Calls] = field(default_factory=lambda: {name: Calls() for name in ENDPOINTS})
    flow_errors: Counter[str] = field(default_factory=Counter)
    events: Counter[str] = field(default_factory=Counter)
    streams_opened: int = 0
    sessions_started: int = 0
    sessions_completed: int = 0
    session_seconds: list[float] = field(default_factory=list)
    finished_at: list[float] = field(default_factory=list)  # monotonic, completed sessions
    state_fetches_per_phone: list[int] = field(default_factory=list)
    sessions_in_flight: int = 0
    streams_open: int = 0
    requests_in_flight: int = 0
    samples: list[Sample] = field(default_factory=list)
    loop_lag_ms: list[float] = field(default_factory=list)

    def ok(self, endpoint: str, latency_ms: float, response: httpx.Response) -> None:
        calls = self.calls[endpoint]
        calls.latency_ms.append(latency_ms)
        with suppress(KeyError, IndexError, ValueError):
            header = response.headers["server-timing"]
            calls.server_ms.append(float(header.split("dur=", 1)[1].split(";")[0].split(",")[0]))

    def failed(self, endpoint: str, kind: str) -> None:
        self.calls[endpoint].errors[kind] += 1

    def flow(self, kind: str) -> None:
        """Something a phone expected and did not see (an event, a stream that dropped)."""
        self.flow_errors[kind] += 1

    @property
    def http_errors(self) -> int:
        return sum(sum(calls.errors.values()) for calls in self.calls.values())

    @property
    def errors(self) -> int:
        return self.http_errors + sum(self.flow_errors.values())


def error_kind(response: httpx.Response) -> str:
    """``HTTP 503 busy``: the status and the API's error code, when it sent one."""
    code = ""
    with suppress(ValueError, KeyError, TypeError):
        code = " " + str(response.json()["error"]["code"])
    return f"HTTP {response.status_code}{code}"


# --- one phone -------------------------------------------------------------------------------


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
    if change.type == "result":
        answered = shown.get("result") is not None or shown.get("result_error") is not None
        return shown["version"] > change.version or (
            shown["version"] == change.version and answered
        )
    return bool(shown["version"] >= change.version)


class Phone:
    """One participant: its own HTTP client (keep-alive, a browser's few connections), its
    calls, its event stream, the state it shows."""

    def __init__(self, driver: Driver, role: str) -> None:
        self.driver = driver
        self.rec = driver.rec
        self.role = role
        self.http = driver.client()
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
    ) -> httpx.Response | None:
        """One request, timed and recorded; None unless it answered ``expect``."""
        rec = self.rec
        rec.requests_in_flight += 1
        started = time.perf_counter()
        try:
            response = await self.http.request(method, url, headers=self.auth, **options)
        except httpx.TimeoutException:
            rec.failed(endpoint, "timeout")
            return None
        except httpx.TransportError as error:
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
            new_answer = state.get("result") is not None and state["result_version"] != self.drawn
            if new_answer and (self.drawing is None or self.drawing.done()):
                self.drawing = asyncio.create_task(self._draw())

    async def _draw(self) -> None:
        while not self.ending and self.state is not None and self.state.get("result"):
            version = self.state["result_version"]
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
        timeout = httpx.Timeout(REQUEST_SECONDS, read=STREAM_READ_SECONDS)
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
        except httpx.TimeoutException:
            if opened:
                self.rec.flow("stream silent too long (read timeout)")
            else:
                self.rec.failed(EVENTS, "timeout")
        except httpx.TransportError as error:
            if opened:
                self.rec.flow(f"stream dropped ({type(error).__name__})")
            else:
                self.rec.failed(EVENTS, type(error).__name__)
        finally:
            if opened:
                self.rec.streams_open -= 1

    async def _read(self, response: httpx.Response) -> None:
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
        with suppress(httpx.HTTPError):
            await self.http.delete(self.url(), headers=self.auth, timeout=CLEANUP_SECONDS)

    async def close(self) -> None:
        """Stop its tasks (a failed session: the stream may still be open), close its client."""
        for task in (self.stream, self.fetching, self.drawing):
            if task is not None and not task.done():
                task.cancel()
                with suppress(asyncio.CancelledError, Exception):
                    await task
        await self.http.aclose()


# --- the driver: the sessions ----------------------------------------------------------------


class Driver:
    """Plays both phones of many sessions against one server."""

    def __init__(
        self,
        base_url: str,
        photos: tuple[bytes, bytes],
        scenes: list[Scene],
        speed: float,
        seed: int,
    ) -> None:
        self.base_url = base_url
        self.photos = photos
        self.scenes = scenes
        self.speed = speed
        self.seed = seed
        self.rec = Recorder()
        # Never used (plain HTTP on loopback), but httpx builds one per client unless given
        # one: loading the CA bundle costs 35 ms per client.
        self.tls = ssl.create_default_context()

    def client(self) -> httpx.AsyncClient:
        """A phone's own client. One client shared by all phones would hold hundreds of
        connections, and httpcore's pool does work quadratic in that number per request."""
        # Idle connections closed before uvicorn closes them (after 5 s): a request sent on
        # a connection the server is closing fails. A browser sends it again on a new one;
        # httpx does not, so it must not reuse a connection that old.
        limits = httpx.Limits(
            max_connections=PHONE_CONNECTIONS,
            max_keepalive_connections=PHONE_CONNECTIONS,
            keepalive_expiry=KEEPALIVE_SECONDS,
        )
        return httpx.AsyncClient(
            base_url=self.base_url, limits=limits, timeout=REQUEST_SECONDS, verify=self.tls
        )

    async def pause(self, rng: np.random.Generator, step: str) -> None:
        """A person doing ``step`` (one of PAUSES)."""
        await asyncio.sleep(rng.uniform(*PAUSES[step]) / self.speed)

    async def create(self) -> tuple[Phone, str] | None:
        """The seeker's phone with a new session, and the join code; None if refused."""
        seeker = Phone(self, "seeker")
        created = await seeker.call(CREATE, "POST", "/api/sessions", expect=201)
        if created is None:
            await seeker.close()
            return None
        body = created.json()
        seeker.enter(body["session_id"], body["token"])
        return seeker, str(body["join_code"])

    async def join(self, code: str) -> Phone | None:
        """The buddy's phone, joined with ``code``; None if refused."""
        buddy = Phone(self, "buddy")
        joined = await buddy.call(JOIN, "POST", "/api/sessions/join", json={"code": code})
        if joined is None:
            await buddy.close()
            return None
        body = joined.json()
        buddy.enter(body["session_id"], body["token"])
        return buddy

    async def pair(self, rng: np.random.Generator | None = None) -> tuple[Phone, Phone] | None:
        """The seeker creates a session and listens; the buddy joins with the code (after
        a person's pause, given ``rng``) and listens. None if any of it failed."""
        created = await self.create()
        if created is None:
            return None
        seeker, code = created
        seeker.listen()
        seeker.refetch()  # the phone shows the state (the QR code) at once
        if rng is not None:
            await self.pause(rng, "join")
        buddy = await self.join(code)
        if buddy is None:
            await seeker.discard()
            await seeker.close()
            return None
        buddy.listen()
        buddy.refetch()
        return seeker, buddy

    async def session(self, number: tuple[int, int]) -> bool:
        """One whole session; True when everything in it went as a phone expects."""
        rng = np.random.default_rng([self.seed, *number])
        taps = session_taps(self.scenes[int(rng.integers(len(self.scenes)))], rng)
        started = time.monotonic()
        self.rec.sessions_started += 1
        paired = await self.pair(rng)
        if paired is None:
            return False
        seeker, buddy = paired
        deleted = complete = False
        try:
            sides = await asyncio.gather(
                self.seeker_side(seeker, taps, rng), self.buddy_side(buddy, taps, rng)
            )
            if not all(sides):
                return False
            answer = [await phone.wait_for(has_answer, "the answer") for phone in paired]
            await self.pause(rng, "read")  # they read the answer, wave, find each other
            deleted = await self.delete(seeker, buddy)
            if not deleted:
                return False
            ended = [await phone.wait_event(phone.expired, "'expired'") for phone in paired]
            complete = all(answer) and all(ended)
            for phone in paired:
                missing = [kind for kind in EXPECTED_EVENTS if not phone.events[kind]]
                for kind in missing:
                    self.rec.flow(f"the {phone.role}'s stream never saw '{kind}'")
                complete = complete and not missing
                self.rec.state_fetches_per_phone.append(phone.fetches)
        finally:
            if not deleted:  # a failed or cut-off session: gone from the server all the same
                await seeker.discard()
            for phone in paired:
                await phone.close()
        if complete:
            self.rec.sessions_completed += 1
            self.rec.session_seconds.append(time.monotonic() - started)
            self.rec.finished_at.append(time.monotonic())
        return complete

    async def delete(self, seeker: Phone, *others: Phone) -> bool:
        for phone in (seeker, *others):
            await phone.settled()
        return await seeker.call(DELETE, "DELETE", seeker.url(), expect=204) is not None

    async def seeker_side(self, phone: Phone, taps: SessionTaps, rng: np.random.Generator) -> bool:
        """Its photo, then the buddy mark and one more landmark per PUT."""
        if not await phone.wait_event(phone.live, "own 'joined'"):
            return False
        await self.pause(rng, "photo")
        if not await self.upload(phone, self.photos[0]):
            return False
        for n in range(1, LANDMARKS + 1):
            await self.pause(rng, "tap")
            body = {"landmarks": taps.seeker[:n], "epipole1": taps.buddy_mark}
            if not await phone.put_taps(body):
                return False
        return True

    async def buddy_side(self, phone: Phone, taps: SessionTaps, rng: np.random.Generator) -> bool:
        """Its photo; then, for each landmark the seeker taps, "find #n" (its crop) and the
        tap. (Each phone loads its overlay whenever its state shows a new answer.)"""
        if not await phone.wait_event(phone.live, "own 'joined'"):
            return False
        await self.pause(rng, "photo")
        if not await self.upload(phone, self.photos[1]):
            return False
        for n in range(1, LANDMARKS + 1):
            if not await self.find_and_tap(phone, n, taps.buddy[:n], rng):
                return False
        return True

    async def find_and_tap(
        self, phone: Phone, n: int, landmarks: list[dict[str, float]], rng: np.random.Generator
    ) -> bool:
        """The buddy's landmark #n: once the seeker's #n shows, its crop, then the tap."""
        if not await phone.wait_for(seeker_tapped(n), f"the seeker's landmark #{n}"):
            return False
        if await self.crop(phone, n) is None:
            return False
        await self.pause(rng, "find")
        return await phone.put_taps({"landmarks": landmarks})

    async def crop(self, phone: Phone, n: int) -> httpx.Response | None:
        """The seeker's landmark #n as the buddy's <img> gets it (``?token=``, a cache key)."""
        assert phone.state is not None
        seen = next(t for t in phone.state["taps"]["seeker"]["landmarks"] if t["id"] == n)
        params = {"token": phone.token, "v": f"{seen['x']},{seen['y']}"}
        return await phone.call(
            CROP, "GET", phone.url(f"/landmarks/seeker/{n}/crop"), params=params
        )

    async def overlay(self, phone: Phone) -> httpx.Response | None:
        assert phone.state is not None
        params = {"token": phone.token, "v": str(phone.state["result_version"])}
        return await phone.call(OVERLAY, "GET", phone.url(f"/overlay/{phone.role}"), params=params)

    async def upload(self, phone: Phone, photo: bytes) -> bool:
        """The photo, then the stored one as the app loads it to tap on."""
        return await self.put_photo(phone, photo) and await self.stored(phone)

    async def put_photo(self, phone: Phone, photo: bytes) -> bool:
        files = {"photo": ("photo.jpg", photo, "image/jpeg")}
        return await phone.call(PHOTO, "PUT", phone.url("/photo"), files=files) is not None

    async def stored(self, phone: Phone) -> bool:
        """Its stored photo, as the app's <img> loads it (``?token=``, a cache key)."""
        params = {"token": phone.token, "v": "1"}
        stored = await phone.call(STORED, "GET", phone.url(f"/photo/{phone.role}"), params=params)
        return stored is not None


def has_answer(state: dict[str, Any]) -> bool:
    return state.get("result") is not None


def seeker_tapped(n: int) -> Callable[[dict[str, Any]], bool]:
    def tapped(state: dict[str, Any]) -> bool:
        seeker = state["taps"].get("seeker")
        return seeker is not None and any(t["id"] == n for t in seeker["landmarks"])

    return tapped


# --- the phases ------------------------------------------------------------------------------


async def sample_forever(rec: Recorder, server_pids: Sequence[int]) -> None:
    """Every SAMPLE_SECONDS: the CPU counters and how much is in flight."""
    while True:
        rec.samples.append(
            Sample(
                cpu_snapshot(server_pids),
                rec.sessions_in_flight,
                rec.streams_open,
                rec.requests_in_flight,
            )
        )
        await asyncio.sleep(SAMPLE_SECONDS)


async def probe_loop_lag(rec: Recorder) -> None:
    """How late this process's event loop wakes a sleeper: the load generator's own delay,
    which every latency measured here includes."""
    while True:
        started = time.perf_counter()
        await asyncio.sleep(LAG_PROBE_SECONDS)
        rec.loop_lag_ms.append((time.perf_counter() - started - LAG_PROBE_SECONDS) * 1000)


@contextmanager
def background(*tasks: asyncio.Task[None]) -> Iterator[None]:
    try:
        yield
    finally:
        for task in tasks:
            task.cancel()


@dataclass(frozen=True)
class Solo:
    rec: Recorder
    cpu: CpuUse
    sessions: int


async def solo(driver: Driver, server_pids: Sequence[int]) -> Solo:
    """SOLO_SESSIONS sessions one at a time: no queueing anywhere."""
    first = cpu_snapshot(server_pids)
    for k in range(SOLO_SESSIONS):
        await driver.session((0, k))
    return Solo(driver.rec, CpuUse.between(first, cpu_snapshot(server_pids)), SOLO_SESSIONS)


STREAM = "event stream: open until live, close"


@dataclass(frozen=True)
class Costs:
    """Server CPU per call, ms, with one call in flight at a time and no other stream open."""

    cpu_ms: dict[str, float]
    calls: int  # of each kind
    failed: int


async def call_costs(driver: Driver, server_pids: Sequence[int], poll: float) -> Costs:
    """COST_CALLS calls of each kind, one at a time, the server's CPU read around each: new
    sessions (create, join, the seeker's photo, delete); on one session with both photos
    and 6 + 6 landmarks: taps (each moves the buddy's #1 by 0.5 px, so the answer is solved
    again), state, crops, uncached overlays (each after such a move); and each buddy's event
    stream opened until live, then closed (the server notices at its next poll and writes
    the phone offline: waited for)."""
    spent: dict[str, float] = {}
    failed = 0
    seekers: list[Phone] = []
    codes: list[str] = []
    buddies: list[Phone] = []

    def cpu() -> float:
        return cpu_snapshot(server_pids).server

    async def each(name: str, calls: Sequence[Callable[[], Awaitable[object]]]) -> None:
        nonlocal failed
        total = 0.0
        for call in calls:
            before = cpu()
            failed += await call() in (None, False)
            total += cpu() - before
        spent[name] = 1000 * total / max(len(calls), 1)

    async def create() -> object:
        created = await driver.create()
        if created is not None:
            seekers.append(created[0])
            codes.append(created[1])
        return created

    async def join(code: str) -> object:
        buddy = await driver.join(code)
        if buddy is not None:
            buddy.ending = True  # its streams below: no state fetches
            buddies.append(buddy)
        return buddy

    await each(CREATE, [create] * COST_CALLS)
    await each(JOIN, [partial(join, code) for code in codes])
    await each(PHOTO, [partial(driver.put_photo, seeker, driver.photos[0]) for seeker in seekers])
    await each(STORED, [partial(driver.stored, seeker) for seeker in seekers])
    if not buddies:
        return Costs(spent, COST_CALLS, failed + COST_CALLS)
    seeker, buddy = seekers[0], buddies[0]
    taps = session_taps(driver.scenes[0], np.random.default_rng([driver.seed, 2]))
    await driver.put_photo(buddy, driver.photos[1])
    mark = {"landmarks": taps.seeker, "epipole1": taps.buddy_mark}
    await seeker.call(TAPS, "PUT", seeker.url("/taps"), json=mark)
    landmarks = [dict(t) for t in taps.buddy]

    async def move() -> httpx.Response | None:
        landmarks[0]["x"] += 0.5 if landmarks[0]["x"] < PHOTO_SIZE[0] / 2 else -0.5
        answered = await buddy.call(TAPS, "PUT", buddy.url("/taps"), json={"landmarks": landmarks})
        if answered is not None:
            await buddy.show(answered.json())
        return answered

    async def overlay() -> object:
        await move()
        before = cpu()
        drawn = await driver.overlay(buddy)
        spent[OVERLAY] = spent.get(OVERLAY, 0.0) + 1000 * (cpu() - before) / COST_CALLS
        return drawn

    await each(TAPS, [move] * COST_CALLS)
    await each(STATE, [partial(buddy.call, STATE, "GET", buddy.url())] * COST_CALLS)
    await each(CROP, [partial(driver.crop, buddy, 1 + k % LANDMARKS) for k in range(COST_CALLS)])
    for _ in range(COST_CALLS):
        failed += await overlay() is None
    before = cpu()
    for phone in buddies:
        phone.listen()
    live = [await phone.wait_event(phone.live, "own 'joined'") for phone in buddies]
    for phone in buddies:
        assert phone.stream is not None
        phone.stream.cancel()
        with suppress(asyncio.CancelledError):
            await phone.stream
    await asyncio.sleep(poll + 0.5)  # until the server has noticed and written it
    spent[STREAM] = 1000 * (cpu() - before) / len(buddies)
    failed += live.count(False)
    await each(DELETE, [partial(driver.delete, seeker) for seeker in seekers])
    for phone in seekers + buddies:
        await phone.close()
    return Costs(spent, COST_CALLS, failed)


@dataclass(frozen=True)
class Idle:
    rec: Recorder
    cpu: CpuUse
    streams: int
    poll_seconds: float


async def idle_streams(
    driver: Driver, server_pids: Sequence[int], sessions: int, seconds: float, poll: float
) -> Idle:
    """``sessions`` sessions paired, both streams open, nobody doing anything for
    ``seconds``: the server's CPU then is what the open streams cost."""
    gate = asyncio.Semaphore(PAIRING_CONCURRENCY)

    async def paired() -> tuple[Phone, Phone] | None:
        async with gate:
            pair = await driver.pair()
            if pair is not None:
                for phone in pair:
                    await phone.wait_event(phone.live, "own 'joined'")
                    await phone.settled()
            return pair

    pairs = [p for p in await asyncio.gather(*(paired() for _ in range(sessions))) if p]
    await asyncio.sleep(SETTLE_SECONDS)
    streams = driver.rec.streams_open
    first = cpu_snapshot(server_pids)
    await asyncio.sleep(seconds)
    cpu = CpuUse.between(first, cpu_snapshot(server_pids))

    async def ended(seeker: Phone, buddy: Phone) -> None:
        async with gate:
            if await driver.delete(seeker, buddy):
                for phone in (seeker, buddy):
                    await phone.wait_event(phone.expired, "'expired'")
            for phone in (seeker, buddy):
                await phone.close()

    await asyncio.gather(*(ended(*pair) for pair in pairs))
    return Idle(driver.rec, cpu, streams, poll)


@dataclass(frozen=True)
class Load:
    rec: Recorder
    concurrency: int
    started_at: float  # monotonic
    steady_from: float  # the ramp is over
    stopped_at: float  # no session starts after this
    ended_at: float
    cut_off: int  # sessions still running at the hard limit


async def load(driver: Driver, server_pids: Sequence[int], setup: Setup) -> Load:
    """``setup.concurrency`` slots, each running sessions back to back from its start
    (staggered over ``setup.ramp`` s) until ``setup.duration`` s have passed or
    ``setup.budget`` sessions have started; the sessions still running then get
    DRAIN_SECONDS to finish."""
    rec = driver.rec
    concurrency, duration, ramp, budget = (
        setup.concurrency,
        setup.duration,
        setup.ramp,
        setup.budget,
    )
    started = time.monotonic()
    stop_at = started + duration
    cut_off = 0

    async def slot(index: int) -> None:
        await asyncio.sleep(index * ramp / concurrency)
        for k in range(MAX_SESSIONS_PER_SLOT):
            if time.monotonic() >= stop_at or (
                budget is not None and rec.sessions_started >= budget
            ):
                return
            rec.sessions_in_flight += 1
            try:
                await driver.session((1 + index, k))
            except Exception as error:  # a bug of this script: counted, and the slot goes on
                rec.flow(f"load generator error: {type(error).__name__}: {error}")
            finally:
                rec.sessions_in_flight -= 1

    sampler = asyncio.create_task(sample_forever(rec, server_pids))
    lag = asyncio.create_task(probe_loop_lag(rec))
    with background(sampler, lag):
        slots = [asyncio.create_task(slot(i)) for i in range(concurrency)]
        _, running = await asyncio.wait(slots, timeout=duration + DRAIN_SECONDS)
        cut_off = len(running)
        for task in running:
            task.cancel()
        await asyncio.gather(*running, return_exceptions=True)
        rec.samples.append(
            Sample(cpu_snapshot(server_pids), rec.sessions_in_flight, rec.streams_open, 0)
        )
    if cut_off:
        rec.flow_errors["session cut off by the time limit"] += cut_off
    return Load(rec, concurrency, started, started + ramp, stop_at, time.monotonic(), cut_off)


# --- the server ------------------------------------------------------------------------------


@contextmanager
def database(kind: str, folder: Path) -> Iterator[str]:
    """The URL of a new, empty database: a SQLite file in ``folder``, or a database on a
    throwaway PostgreSQL server (the tests' ``tests/postgres.py``: Debian's binaries, a
    loopback port, a temporary folder)."""
    if kind == "sqlite":
        yield f"sqlite:///{folder / 'load.db'}"
        return
    spec = importlib.util.spec_from_file_location("postgres", ROOT / "tests" / "postgres.py")
    if spec is None or spec.loader is None:
        raise RuntimeError("tests/postgres.py is missing")
    postgres = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(postgres)
    server = postgres.PostgresServer()
    try:
        server.start()
        yield str(server.url(server.create_database()))
    finally:
        server.remove()


def describe_database(url: str) -> str:
    """What the app made of the database: SQLite's journal mode, or PostgreSQL's version;
    and the connection pool each server process has (the app's own engine settings)."""
    engine = connect(url)
    pool = engine.pool
    size = getattr(pool, "size", lambda: None)()
    overflow = getattr(pool, "_max_overflow", None)
    pooled = f"{type(pool).__name__} of {size} + {overflow} overflow connections per process"
    try:
        if engine.dialect.name == "sqlite":
            path = url.removeprefix("sqlite:///")
            with closing(sqlite3.connect(path)) as sqlite:
                mode = str(sqlite.execute("PRAGMA journal_mode").fetchone()[0])
            return f"SQLite {sqlite3.sqlite_version}, journal mode {mode}, {pooled}"
        with engine.connect() as connection:
            server = connection.exec_driver_sql("SHOW server_version").scalar()
        return f"PostgreSQL {server} (throwaway server on loopback), {pooled}"
    finally:
        engine.dispose()


# --- the report ----------------------------------------------------------------------------


def percentile(values: Sequence[float], q: float) -> float:
    if not values:
        return float("nan")
    return float(np.percentile(np.asarray(values, dtype=np.float64), q))


def ms(value: float) -> str:
    if math.isnan(value):  # nothing measured
        return "-"
    return f"{value:.2f}" if value < 10 else f"{value:.1f}" if value < 100 else f"{value:.0f}"


def git(*args: str) -> str:
    return subprocess.run(
        ["git", *args], cwd=ROOT, capture_output=True, text=True, check=True, timeout=30
    ).stdout


def source_state() -> str:
    """The commit, and any uncommitted changes to the code under test."""
    try:
        commit = git("rev-parse", "--short", "HEAD").strip()
        changed = git("status", "--porcelain", "--", "backend", "shared_solver").splitlines()
    except (OSError, subprocess.CalledProcessError, subprocess.TimeoutExpired):
        return "not a git checkout"
    files = [line[3:] for line in changed if line.strip()]
    return f"commit {commit}" + (
        f", uncommitted changes in {', '.join(files)}" if files else ", no uncommitted changes"
    )


async def default_threads() -> int:
    return int(anyio.to_thread.current_default_thread_limiter().total_tokens)


@dataclass(frozen=True)
class Setup:
    argv: list[str]
    concurrency: int
    duration: float
    budget: int | None
    ramp: float
    idle_seconds: float
    speed: float
    workers: int
    database_kind: str
    event_poll_seconds: float | None  # BUDDY_EVENT_POLL_SECONDS for the server; None: default
    seed: int


@dataclass(frozen=True)
class Results:
    setup: Setup
    settings: Settings
    database: str
    photo_bytes: tuple[int, int]
    costs: Costs
    solo: Solo
    idle: Idle | None
    load: Load
    server_memory_mb: list[float]  # VmHWM of each server process
    timings: dict[str, float]


def header(results: Results) -> str:
    setup, settings = results.setup, results.settings
    now = datetime.now().astimezone().isoformat(timespec="seconds")
    names = ("uvicorn", "fastapi", "starlette", "anyio", "h11", "httpx", "sqlalchemy", "numpy")
    versions = ", ".join(f"{name} {version(name)}" for name in names)
    threads = asyncio.run(default_threads())
    workers = (
        "one worker process"
        if setup.workers == 1
        else f"{setup.workers} worker processes (`WEB_CONCURRENCY={setup.workers}`)"
    )
    seeker_kb, buddy_kb = (size / 1000 for size in results.photo_bytes)
    pauses = ", ".join(
        f"{step} {low / setup.speed:g}-{high / setup.speed:g}"
        for step, (low, high) in PAUSES.items()
    )
    stop = f"for {setup.duration:g} s" + (
        f" or until {setup.budget} sessions have started" if setup.budget else ""
    )
    poll = (
        f"`BUDDY_EVENT_POLL_SECONDS={setup.event_poll_seconds:g}`"
        if setup.event_poll_seconds is not None
        else "the default"
    )
    return "\n".join(
        [
            "# Load benchmark",
            "",
            f"Command: `{shlex.join(['python', 'benchmarks/load.py', *setup.argv])}` "
            "(from the repository root, in its virtualenv; `make bench-load`)",
            "",
            f"- Date: {now}",
            f"- Machine: {platform.platform()}, {platform.machine()}, "
            f"os.cpu_count() = {os.cpu_count()}. **The load generator (this script, one "
            "Python process) runs on the same machine as the server**: both share these cores.",
            f"- Python {platform.python_version()}, {versions}, OpenCV {cv2.__version__}",
            f"- Code under test (backend, shared_solver): {source_state()}",
            "- Server: `python -m uvicorn backend.main:app --host 127.0.0.1 --port <free> "
            f"--no-access-log`, {workers}, {uvicorn_stack()}; loopback only. Sync endpoints "
            f"and the streams' database reads run in anyio's worker threads ({threads} by "
            "default).",
            f"- Database: {results.database}, new and empty at the start"
            + (
                " (PostgreSQL's own processes are not the server's CPU below: they count as "
                "anything else)"
                if setup.database_kind == "postgresql"
                else ""
            )
            + ". Event streams "
            f"re-read the event table every {settings.event_poll_seconds:g} s ({poll}) and when "
            f"woken; pings every {settings.keepalive_seconds:g} s; the other settings are "
            "the defaults.",
            f"- Photos: `{PAIR[0]}.png` (seeker) and `{PAIR[1]}.png` (buddy) upscaled to "
            f"{PHOTO_SIZE[0]}x{PHOTO_SIZE[1]} (bicubic), Gaussian noise sigma "
            f"{PHOTO_NOISE_SIGMA:g}, JPEG quality {PHOTO_QUALITY}: {seeker_kb:.0f} KB and "
            f"{buddy_kb:.0f} KB, stored as they are (under {settings.stored_photo_side} px).",
            f"- Taps: {LANDMARKS} landmarks of a `temple_scene` (the photos' own calibration; "
            f"{SCENES} scenes drawn up front, one picked per session) with {TAP_SIGMA_PX:g} px "
            "tap noise drawn per session; the seeker also marks the buddy (e1). Answers: "
            "`conic` from 4 landmarks, a position from 5 and 6.",
            f"- Load: {setup.concurrency} slots running sessions back to back {stop}, their "
            f"first starts spread over {setup.ramp:g} s. People pause (seconds, uniform, "
            f"seeded {setup.seed}; a person"
            + ("" if setup.speed == 1 else f" sped up {setup.speed:g} times")
            + f"): {pauses}: before joining, each photo, each of the seeker's taps, each of "
            "the buddy's (after its crop) and the delete; sessions still "
            f"running at the end get {DRAIN_SECONDS:g} s. Each phone has its own "
            f"`httpx.AsyncClient` (keep-alive, at most {PHONE_CONNECTIONS} connections, as a "
            f"browser); every call times out after {REQUEST_SECONDS:g} s, a silent stream "
            f"after {STREAM_READ_SECONDS:g} s, a phone waiting for what it expects after "
            f"{WAIT_SECONDS:g} s.",
        ]
    )


def flow_text() -> str:
    return (
        "Each session, as the phone app does it: the seeker `POST /api/sessions` and opens "
        "its event stream (`GET /events?token=`, open until the end, read continuously); "
        "the buddy joins with the code and opens its stream; each phone fetches the state "
        "after every event that tells it something its screen does not show yet (the app's "
        "`alreadyShown`: a phone's own taps come back with the answer in the reply to its "
        "PUT; news told while that PUT is on its way waits for the reply), at most one "
        "fetch in flight per phone, one more if events came meanwhile, and shows the "
        "newest. Once its stream is live, each phone uploads its photo and loads the stored "
        f"one (`GET /photo/<own role>`). The seeker sends `PUT /taps` {LANDMARKS} times: "
        "the buddy mark and one more landmark each time. For each landmark #n the buddy "
        "waits until its state shows the seeker's #n, gets its crop (`GET "
        '/landmarks/seeker/n/crop`: "find #n"), pauses and sends its own landmarks #1..#n '
        "(`PUT /taps`: the answer is recomputed in the request). Each phone loads its "
        "overlay (`GET /overlay/<own role>`, JPEG) whenever its state shows a new answer; "
        "both phones wait until their state shows it; the seeker sends "
        "`DELETE`, and both streams must end with `expired`. Errors: any call that is not "
        "the expected 2xx or times out; a stream that drops, goes silent, or ends without "
        f"`expired`; a stream that never saw one of {', '.join(EXPECTED_EVENTS)}; a phone "
        f"that waited over {WAIT_SECONDS:g} s for what it expected."
    )


def endpoint_rows(rec: Recorder) -> list[list[str]]:
    rows = []
    for name in ENDPOINTS:
        calls = rec.calls[name]
        latency, server = calls.latency_ms, calls.server_ms
        rows.append(
            [
                f"`{name}`" + (" (no target)" if name in EXEMPT else ""),
                str(len(latency) + sum(calls.errors.values())),
                ms(percentile(latency, 50)),
                ms(percentile(latency, 95)),
                ms(percentile(latency, 99)),
                ms(max(latency, default=float("nan"))),
                f"{ms(percentile(server, 50))} / {ms(percentile(server, 99))}",
                str(sum(calls.errors.values())),
            ]
        )
    every = [v for name in ENDPOINTS for v in rec.calls[name].latency_ms]
    rows.append(
        [
            "**all calls**",
            str(len(every) + rec.http_errors),
            ms(percentile(every, 50)),
            ms(percentile(every, 95)),
            ms(percentile(every, 99)),
            ms(max(every, default=float("nan"))),
            "",
            str(rec.http_errors),
        ]
    )
    return rows


def endpoint_table(rec: Recorder) -> str:
    return markdown_table(
        [
            "call",
            "calls",
            "p50 (ms)",
            "p95 (ms)",
            "p99 (ms)",
            "max (ms)",
            "Server-Timing p50 / p99 (ms)",
            "errors",
        ],
        endpoint_rows(rec),
    )


def steady(load_: Load) -> tuple[list[Sample], CpuUse]:
    """The samples between the end of the ramp and the last session start, and the CPU
    used meanwhile."""
    window = [s for s in load_.rec.samples if load_.steady_from <= s.cpu.at <= load_.stopped_at]
    if len(window) < 2:
        window = load_.rec.samples
    return window, CpuUse.between(window[0].cpu, window[-1].cpu)


def whole(load_: Load) -> CpuUse:
    """The CPU used over the whole load phase, drain included."""
    return CpuUse.between(load_.rec.samples[0].cpu, load_.rec.samples[-1].cpu)


def sessions_per_second(load_: Load) -> tuple[float, float]:
    """Completed sessions per second: over the whole phase (drain included), and those
    completed within the steady window per second of it."""
    rec = load_.rec
    rate = rec.sessions_completed / max(load_.ended_at - load_.started_at, 1e-9)
    inside = [t for t in rec.finished_at if load_.steady_from <= t <= load_.stopped_at]
    return rate, len(inside) / max(load_.stopped_at - load_.steady_from, 1e-9)


def streams_held(load_: Load) -> tuple[float, float]:
    """Steady medians of the sessions in flight and of the event streams open."""
    window, _ = steady(load_)
    return (
        percentile([s.sessions for s in window], 50),
        percentile([s.streams for s in window], 50),
    )


def load_section(results: Results) -> list[str]:
    load_ = results.load
    rec = load_.rec
    window, cpu = steady(load_)
    whole_rate, steady_rate = sessions_per_second(load_)
    requests = [s.requests for s in window]
    duration = rec.session_seconds
    fetches = rec.state_fetches_per_phone
    held, open_streams = streams_held(load_)
    events = ", ".join(f"{k} {v}" for k, v in rec.events.items())
    memory = results.server_memory_mb
    lag = rec.loop_lag_ms
    rows = [
        ["sessions started / completed", f"{rec.sessions_started} / {rec.sessions_completed}"],
        [
            "completed sessions per second: whole phase / steady window",
            f"{whole_rate:.2f} / {steady_rate:.2f}",
        ],
        [
            "session duration p50 / p95 / max (s)",
            f"{percentile(duration, 50):.1f} / {percentile(duration, 95):.1f} / "
            f"{max(duration, default=float('nan')):.1f}",
        ],
        [
            "sessions in flight: steady median / peak",
            f"{held:.0f} / {max(s.sessions for s in rec.samples)}",
        ],
        [
            "event streams open: steady median / peak",
            f"{open_streams:.0f} / {max(s.streams for s in rec.samples)}",
        ],
        [
            "calls in flight (streams aside): steady median / peak",
            f"{percentile(requests, 50):.0f} / {max(requests, default=0)}",
        ],
        [
            "events received per stream",
            f"{sum(rec.events.values()) / max(rec.streams_opened, 1):.1f} ({events})",
        ],
        [
            "state fetches per phone: median / max",
            f"{percentile(fetches, 50):.0f} / {max(fetches, default=0)}",
        ],
        [
            "CPU in the steady window, cores: server / load generator / anything else",
            f"{cpu.server:.2f} / {cpu.client:.2f} / {cpu.others:.2f} "
            f"(machine {percent(cpu.machine)} busy)",
        ],
        [
            "server peak memory (VmHWM)",
            " + ".join(f"{m:.0f} MB" for m in memory)
            + (f" ({len(memory)} processes under uvicorn's supervisor)" if len(memory) > 1 else ""),
        ],
        [
            "load generator's event loop lag p50 / p99 / max (ms)",
            f"{ms(percentile(lag, 50))} / {ms(percentile(lag, 99))} / "
            f"{ms(max(lag, default=float('nan')))}",
        ],
        [
            "errors: failed calls / flow errors",
            f"{rec.http_errors} / {sum(rec.flow_errors.values())}",
        ],
    ]
    lines = [
        "## Under load",
        f"{load_.concurrency} sessions at once, so up to {2 * load_.concurrency} event "
        "streams. The steady window runs from the end of the ramp to the last session start "
        f"({load_.stopped_at - load_.steady_from:.0f} s). Latency is the client's: request "
        "sent to response read (for the stream: to its headers), measured in the load "
        "generator, so it includes the load generator's own delays (its event loop lag, "
        "below). Server-Timing is the app's time from the request's arrival to its "
        "response's start (not the time a request waits in uvicorn before the app sees it).",
        endpoint_table(rec),
        markdown_table(["measured", "value"], rows),
    ]
    return lines + error_kinds(rec)


def error_kinds(rec: Recorder) -> list[str]:
    """The table of what failed, if anything did."""
    if not rec.errors:
        return []
    kinds = [
        [f"`{name}`", kind, str(count)]
        for name in ENDPOINTS
        for kind, count in rec.calls[name].errors.most_common()
    ] + [["(flow)", kind, str(count)] for kind, count in rec.flow_errors.most_common()]
    return ["Errors by kind:", markdown_table(["call", "error", "count"], kinds)]


@dataclass(frozen=True)
class Budget:
    """Server CPU per session, modelled from the cost of each call alone and the calls a
    quiet session makes, against what a quiet session measured."""

    rows: list[tuple[str, float, float]]  # call, CPU per call (ms), calls per session
    polling_ms: float  # both streams' polls over a quiet session's life
    session_seconds: float  # a quiet session's median duration
    measured_ms: float  # server CPU per quiet session, streams included

    @property
    def modelled_ms(self) -> float:
        return sum(cost * count for _, cost, count in self.rows) + self.polling_ms


def budget(results: Results) -> Budget:
    solo_ = results.solo
    sessions = max(solo_.rec.sessions_completed, 1)
    counts = {
        name: (len(calls.latency_ms) + sum(calls.errors.values())) / sessions
        for name, calls in solo_.rec.calls.items()
    }
    costs = results.costs.cpu_ms
    rows = [(name, costs[name], counts[name]) for name in ENDPOINTS if name in costs]
    rows.append((STREAM, costs.get(STREAM, float("nan")), 2.0))
    # A session's streams stay open as long as it lasts at the load's pace.
    seconds = percentile(results.load.rec.session_seconds or solo_.rec.session_seconds, 50)
    per_stream_second = 0.0
    if results.idle is not None and results.idle.streams:
        per_stream_second = 1000 * results.idle.cpu.server / results.idle.streams
    measured = 1000 * solo_.cpu.server * solo_.cpu.seconds / sessions
    return Budget(rows, 2 * seconds * per_stream_second, seconds, measured)


def cost_section(results: Results) -> list[str]:
    model = budget(results)
    rows = [
        [f"`{name}`" if name != STREAM else name, ms(cost), f"{count:.1f}", ms(cost * count)]
        for name, cost, count in model.rows
    ]
    rows.append(
        [
            "both streams polling the event table",
            "",
            "",
            ms(model.polling_ms),
        ]
    )
    rows.append(["**modelled total**", "", "", f"**{ms(model.modelled_ms)}**"])
    rows.append(["measured: a quiet session, everything", "", "", ms(model.measured_ms)])
    lines = [
        "## Where the server's CPU goes",
        f"Server CPU per call, each call alone ({results.costs.calls} of each, one at a time, "
        "from /proc: the HTTP layer included), times the calls one session makes on a quiet "
        f"server ({results.solo.sessions} sessions, below); event-stream polling from the "
        f"idle streams, over a session's median length under load, "
        f"{model.session_seconds:.1f} s. Failed calls "
        f"while measuring: {results.costs.failed}.",
        markdown_table(
            ["call", "server CPU per call (ms)", "calls per session", "CPU per session (ms)"],
            rows,
        ),
    ]
    idle_ = results.idle
    if idle_ is not None:
        per_stream_ms = 1000 * idle_.cpu.server / max(idle_.streams, 1)
        lines.append(
            f"Idle streams: {idle_.streams // 2} sessions paired with both streams open "
            f"({idle_.streams} streams) and nobody tapping, for {idle_.cpu.seconds:.1f} s: "
            f"the server used {idle_.cpu.server:.3f} cores, {per_stream_ms:.3f} ms of CPU per "
            f"stream per second (each stream re-reads the event table every "
            f"{idle_.poll_seconds:g} s); the load generator {idle_.cpu.client:.3f} cores, "
            f"anything else {idle_.cpu.others:.3f}; errors: {idle_.rec.errors}."
        )
    return lines


def quiet_section(results: Results) -> list[str]:
    solo_ = results.solo
    rec = solo_.rec
    return [
        "## Quiet server",
        f"{solo_.sessions} sessions one at a time (the same flow, pauses {QUIET_SPEED:g} "
        "times shorter): each call's "
        f"time without queueing. Sessions completed: {rec.sessions_completed}; errors: "
        f"{rec.errors}; CPU meanwhile, cores: server {solo_.cpu.server:.2f}, load generator "
        f"{solo_.cpu.client:.2f}, anything else {solo_.cpu.others:.2f}.",
        endpoint_table(rec),
        *error_kinds(rec),
    ]


def targets(results: Results) -> list[str]:
    load_ = results.load
    rec = load_.rec
    held, open_streams = streams_held(load_)
    wanted = STREAMS_HELD * 2 * load_.concurrency
    concurrent = held >= load_.concurrency and open_streams >= wanted
    slow = [
        (name, percentile(rec.calls[name].latency_ms, 99))
        for name in ENDPOINTS
        if name not in EXEMPT and rec.calls[name].latency_ms
    ]
    over = [(name, p99) for name, p99 in slow if not p99 < LATENCY_TARGET_MS]
    worst = max(slow, key=lambda item: item[1]) if slow else ("-", float("nan"))
    incomplete = rec.sessions_started - rec.sessions_completed
    upload = ms(percentile(rec.calls[PHOTO].latency_ms, 99))
    return [
        f"{verdict(concurrent)}: {load_.concurrency} concurrent sessions (steady medians: "
        f"{held:.0f} sessions in flight, {open_streams:.0f} event streams open; at least "
        f"{load_.concurrency} and {wanted:.0f}, {percent(STREAMS_HELD)} of "
        f"{2 * load_.concurrency}, wanted)",
        f"{verdict(rec.errors == 0 and incomplete == 0)}: 0 errors ({rec.http_errors} failed "
        f"calls, {sum(rec.flow_errors.values())} flow errors; {incomplete} of "
        f"{rec.sessions_started} sessions not completed)",
        f"{verdict(not over)}: p99 under {LATENCY_TARGET_MS:g} ms for every call except the "
        "photo upload ("
        + (
            ", ".join(f"`{name}` {ms(p99)} ms" for name, p99 in over)
            if over
            else f"slowest: `{worst[0]}` {ms(worst[1])} ms"
        )
        + f"; photo upload p99 {upload} ms, reported only)",
    ]


def notes(results: Results) -> list[str]:
    """What limited the run, from its own figures."""
    load_ = results.load
    rec = load_.rec
    _, cpu = steady(load_)
    whole_cpu = whole(load_)
    rate, _ = sessions_per_second(load_)
    model = budget(results)
    per_session = model.measured_ms - model.polling_ms  # without the streams' polling
    idle_cores = 0.0
    if results.idle is not None and results.idle.streams:
        idle_cores = results.idle.cpu.server * 2 * load_.concurrency / results.idle.streams
    workers = results.setup.workers
    # Each process runs Python on one core at most (the GIL), and no more than there are.
    cores = min(workers, CORES)
    capacity = 1000 * max(cores - idle_cores, 0.0) / per_session if per_session > 0 else 0.0
    demand = load_.concurrency / model.session_seconds
    loaded_cpu = 1000 * whole_cpu.server * whole_cpu.seconds / max(rec.sessions_completed, 1)
    lines = [
        f"Demand: {load_.concurrency} sessions at once, each {model.session_seconds:.1f} s "
        f"long (the median under load: mostly people's pauses), complete "
        f"{demand:.1f} sessions/s. Supply: a quiet session costs the server "
        f"{model.measured_ms:.0f} ms of CPU ({model.polling_ms:.0f} ms of it its streams' "
        f"polling); {2 * load_.concurrency} open streams cost {idle_cores:.2f} cores by "
        f"themselves (scaled from the idle phase). {workers} server process"
        + ("" if workers == 1 else "es")
        + f" run Python on at most {cores} core"
        + ("" if cores == 1 else "s")
        + " (one each: the GIL), shared with the load generator here, so they can complete "
        f"at most about {capacity:.1f} sessions/s with {2 * load_.concurrency} streams "
        "open: "
        + (
            f"**{demand / capacity:.0f} times less than asked**; the rest waits in queues, "
            "which is the latency above."
            if capacity > 0 and demand > capacity
            else "enough for the demand."
        ),
        "The largest parts of a session's server CPU (the cost table below): "
        + ", ".join(
            f"`{name}` {ms(cost * count)} ms ({count:.0f} x {ms(cost)} ms)"
            for name, cost, count in sorted(
                model.rows, key=lambda row: row[1] * row[2], reverse=True
            )[:3]
        )
        + f"; and the polling of {2 * load_.concurrency} open streams, {idle_cores:.2f} "
        "cores whatever the sessions do.",
        f"Measured under load: {rate:.2f} sessions/s completed, "
        f"{loaded_cpu:.0f} ms of server CPU per completed session (the whole phase, failed "
        f"sessions' work included); server {cpu.server:.2f} cores in the steady window.",
        f"The load generator used {cpu.client:.2f} cores in the steady window; its event "
        f"loop woke sleepers {ms(percentile(rec.loop_lag_ms, 99))} ms late at p99, which "
        "every latency above includes.",
    ]
    others = max(cpu.others, results.solo.cpu.others)
    if others > BUSY_MACHINE_CORES:
        lines.append(
            f"**The machine was not quiet**: programs other than the server and the load "
            f"generator kept up to {others:.2f} cores busy during the run (quiet phase "
            f"{results.solo.cpu.others:.2f}, steady window {cpu.others:.2f}); every time "
            "above is longer for it. Run again on an idle machine to compare."
        )
    pairs = [
        (
            name,
            percentile(rec.calls[name].server_ms, 99),
            percentile(rec.calls[name].latency_ms, 99),
        )
        for name in ENDPOINTS
        if rec.calls[name].latency_ms and rec.calls[name].server_ms
    ]
    if pairs:
        lines.append(
            "p99 Server-Timing / p99 client latency (ms): "
            + ", ".join(f"`{name}` {ms(s)} / {ms(c)}" for name, s, c in pairs)
            + ". The difference is time before the app sees the request (uvicorn's event "
            "loop, shared with the 2N streams and the app's own async code) and in the "
            "load generator."
        )
    return lines


def report(results: Results) -> str:
    spent = ", ".join(f"{name} {s:.1f} s" for name, s in results.timings.items())
    sections = [
        header(results),
        flow_text(),
        "## Targets",
        "\n".join(f"- {line}" for line in targets(results)),
        *load_section(results),
        "What the figures say:",
        "\n".join(f"- {line}" for line in notes(results)),
        *cost_section(results),
        *quiet_section(results),
        f"Wall time: {sum(results.timings.values()):.1f} s ({spent}; interpreter start-up "
        "and imports not included).",
    ]
    return "\n\n".join(sections) + "\n"


# --- running it ----------------------------------------------------------------------------


def log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


@dataclass(frozen=True)
class Measured:
    costs: Costs
    solo: Solo
    idle: Idle | None
    load: Load
    timings: dict[str, float]


async def measure(
    server: Server, setup: Setup, photos: tuple[bytes, bytes], poll: float
) -> Measured:
    scenes = temple_scenes(np.random.default_rng([setup.seed, 0]))
    pids = process_tree(server.pid)
    timings: dict[str, float] = {}

    def driver(speed: float = setup.speed) -> Driver:
        return Driver(server.base_url, photos, scenes, speed, setup.seed)

    log(f"[costs] {COST_CALLS} calls of each kind, one at a time ...")
    began = time.perf_counter()
    costs = await call_costs(driver(), pids, poll)
    timings["costs"] = time.perf_counter() - began
    log(f"[quiet] {SOLO_SESSIONS} sessions one at a time ...")
    began = time.perf_counter()
    quiet = await solo(driver(QUIET_SPEED), pids)
    timings["quiet"] = time.perf_counter() - began
    idle: Idle | None = None
    if setup.idle_seconds > 0:
        log(f"[idle] {setup.concurrency} sessions, streams open, {setup.idle_seconds:g} s ...")
        began = time.perf_counter()
        idle = await idle_streams(driver(), pids, setup.concurrency, setup.idle_seconds, poll)
        timings["idle streams"] = time.perf_counter() - began
    log(f"[load] {setup.concurrency} slots for {setup.duration:g} s ...")
    began = time.perf_counter()
    loaded = await load(driver(), pids, setup)
    timings["load"] = time.perf_counter() - began
    return Measured(costs, quiet, idle, loaded, timings)


def run(setup: Setup) -> Results:
    timings: dict[str, float] = {}
    rng = np.random.default_rng([setup.seed, 1])
    photos = (phone_photo(PAIR[0], rng), phone_photo(PAIR[1], rng))
    with tempfile.TemporaryDirectory(prefix="buddy-load-") as temporary:
        folder = Path(temporary)
        log(f"[server start] {setup.database_kind}, {setup.workers} worker(s) ...")
        began = time.perf_counter()
        with database(setup.database_kind, folder) as url:
            env = {"BUDDY_DATABASE_URL": url, "WEB_CONCURRENCY": str(setup.workers)}
            settings = Settings(_env_file=None, database_url=url)
            if setup.event_poll_seconds is not None:
                env["BUDDY_EVENT_POLL_SECONDS"] = str(setup.event_poll_seconds)
                settings = settings.model_copy(
                    update={"event_poll_seconds": setup.event_poll_seconds}
                )
            with serve(folder, env=env) as server:
                timings["server start"] = time.perf_counter() - began
                log(f"[server] pid {server.pid}, {server.base_url}")
                # Every call, wait and phase is bounded; this bounds them all together.
                limit = OVERALL_SLACK_SECONDS + setup.idle_seconds + setup.duration
                poll_seconds = settings.event_poll_seconds
                measured = asyncio.run(
                    asyncio.wait_for(measure(server, setup, photos, poll_seconds), limit)
                )
                timings |= measured.timings
                pids = process_tree(server.pid)
                if setup.workers > 1:  # the supervisor only starts and watches them
                    pids = [pid for pid in pids if pid != server.pid]
                memory = [peak_memory_mb(pid) for pid in pids]
            described = describe_database(url)
    return Results(
        setup,
        settings,
        described,
        (len(photos[0]), len(photos[1])),
        measured.costs,
        measured.solo,
        measured.idle,
        measured.load,
        memory,
        timings,
    )


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument(
        "--concurrency",
        type=int,
        default=DEFAULT_CONCURRENCY,
        help="sessions in flight at once (default %(default)s)",
    )
    parser.add_argument(
        "--duration",
        type=float,
        default=DEFAULT_DURATION,
        help="seconds during which sessions start (default %(default)s)",
    )
    parser.add_argument(
        "--sessions", type=int, default=None, help="also stop starting sessions after this many"
    )
    parser.add_argument(
        "--ramp",
        type=float,
        default=None,
        help=f"seconds over which the slots start (default {DEFAULT_RAMP:g}, at most a "
        "quarter of the duration)",
    )
    parser.add_argument(
        "--idle-seconds",
        type=float,
        default=DEFAULT_IDLE_SECONDS,
        help="how long to measure idle open streams (0: skip; default %(default)s)",
    )
    parser.add_argument(
        "--speed",
        type=float,
        default=DEFAULT_SPEED,
        help="people this many times quicker than a brisk person (default %(default)s)",
    )
    parser.add_argument(
        "--workers", type=int, default=1, help="uvicorn worker processes (default 1)"
    )
    parser.add_argument(
        "--database",
        choices=("sqlite", "postgresql"),
        default="sqlite",
        help="sqlite (default) or a throwaway PostgreSQL server (tests/postgres.py)",
    )
    parser.add_argument(
        "--event-poll-seconds",
        type=float,
        default=None,
        help="BUDDY_EVENT_POLL_SECONDS for the server (default: the app's)",
    )
    parser.add_argument("--seed", type=int, default=SEED)
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="Markdown report path")
    args = parser.parse_args(argv)
    if not 1 <= args.concurrency <= 2000:
        parser.error("--concurrency must be in [1, 2000]")
    if not 0 < args.duration <= 3600:
        parser.error("--duration must be in (0, 3600]")
    if args.sessions is not None and args.sessions < 1:
        parser.error("--sessions must be at least 1")
    if args.ramp is None:
        args.ramp = min(DEFAULT_RAMP, args.duration / 4)
    if not 0 <= args.ramp <= args.duration or not 0 <= args.idle_seconds <= 600:
        parser.error("--ramp must be in [0, duration], --idle-seconds in [0, 600]")
    if not 0.1 <= args.speed <= 1000:
        parser.error("--speed must be in [0.1, 1000]")
    if not 1 <= args.workers <= 16:
        parser.error("--workers must be in [1, 16]")
    if args.event_poll_seconds is not None and not 0 < args.event_poll_seconds <= 60:
        parser.error("--event-poll-seconds must be in (0, 60]")
    setup = Setup(
        argv=list(sys.argv[1:] if argv is None else argv),
        concurrency=args.concurrency,
        duration=args.duration,
        budget=args.sessions,
        ramp=args.ramp,
        idle_seconds=args.idle_seconds,
        speed=args.speed,
        workers=args.workers,
        database_kind=args.database,
        event_poll_seconds=args.event_poll_seconds,
        seed=args.seed,
    )
    text = report(run(setup))
    print(text, end="")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)


if __name__ == "__main__":
    main()
