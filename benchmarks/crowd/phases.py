"""The phases of a run, in order: the costs of each call alone, a quiet server (sessions
one at a time), idle streams (paired, nobody tapping) and the load itself."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Awaitable, Callable, Iterator, Sequence
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from functools import partial

import httpx2
import numpy as np
from report import cpu_snapshot

from .driver import Driver
from .options import Setup
from .people import LANDMARKS, PHOTO_SIZE, session_taps
from .phone import Phone
from .recorder import (
    CREATE,
    CROP,
    DELETE,
    JOIN,
    OVERLAY,
    PHOTO,
    STATE,
    STORED,
    TAPS,
    Recorder,
    Sample,
)
from .server import CpuUse

QUIET_SPEED = 20.0  # the quiet phase: one session at a time, pauses are only waiting
COST_CALLS = 20  # of each kind, for the server CPU per call
DRAIN_SECONDS = 180.0  # sessions still running at the end of the duration get this long
SETTLE_SECONDS = 2.0  # after the idle streams are open, before their CPU is measured
PAIRING_CONCURRENCY = 20  # sessions paired at once for the idle phase
MAX_SESSIONS_PER_SLOT = 100_000  # a bound, far above what a slot can run
SAMPLE_SECONDS = 1.0
LAG_PROBE_SECONDS = 0.05


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


async def solo(driver: Driver, server_pids: Sequence[int], sessions: int) -> Solo:
    """``sessions`` sessions one at a time: no queueing anywhere."""
    first = cpu_snapshot(server_pids)
    for k in range(sessions):
        await driver.session((0, k))
    return Solo(driver.rec, CpuUse.between(first, cpu_snapshot(server_pids)), sessions)


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
    mark = {"landmarks": taps.seeker, "friend": taps.buddy_mark}
    await seeker.call(TAPS, "PUT", seeker.url("/taps"), json=mark)
    landmarks = [dict(t) for t in taps.buddy]

    async def move() -> httpx2.Response | None:
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
