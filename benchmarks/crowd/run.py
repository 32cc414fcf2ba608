"""One run: the server started on a new database, the phases in order, what they
measured."""

from __future__ import annotations

import asyncio
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from report import log, stopwatch

from backend.settings import Settings
from testbed.loopback import Server, serve

from .driver import Driver
from .options import Setup
from .people import PAIR, phone_photo, temple_scenes
from .phases import (
    COST_CALLS,
    QUIET_SPEED,
    Costs,
    Idle,
    Load,
    Solo,
    call_costs,
    idle_streams,
    load,
    solo,
)
from .server import database, describe_database, peak_memory_mb, process_tree

OVERALL_SLACK_SECONDS = 600.0  # the whole measurement: idle + duration + this, at most


@dataclass(frozen=True)
class Results:
    """Everything the report says: what was asked, the server's set-up, each phase."""

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


@dataclass(frozen=True)
class Measured:
    """What the phases measured, and how long each took."""

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
    with stopwatch(timings, "costs"):
        costs = await call_costs(driver(), pids, poll)
    log(f"[quiet] {setup.quiet_sessions} sessions one at a time ...")
    with stopwatch(timings, "quiet"):
        quiet = await solo(driver(QUIET_SPEED), pids, setup.quiet_sessions)
    idle: Idle | None = None
    if setup.idle_seconds > 0:
        log(f"[idle] {setup.concurrency} sessions, streams open, {setup.idle_seconds:g} s ...")
        with stopwatch(timings, "idle streams"):
            idle = await idle_streams(driver(), pids, setup.concurrency, setup.idle_seconds, poll)
    log(f"[load] {setup.concurrency} slots for {setup.duration:g} s ...")
    with stopwatch(timings, "load"):
        loaded = await load(driver(), pids, setup)
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
