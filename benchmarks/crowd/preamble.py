"""The report's opening: the command, the machine, the server, the database, the photos,
the taps, the load; and the flow of a session."""

from __future__ import annotations

import asyncio
import os
import platform
import shlex
from datetime import datetime
from importlib.metadata import version

import cv2
from report import source_state, uvicorn_stack

from .driver import EXPECTED_EVENTS
from .people import (
    LANDMARKS,
    PAIR,
    PAUSES,
    PHOTO_NOISE_SIGMA,
    PHOTO_QUALITY,
    PHOTO_SIZE,
    SCENES,
    TAP_SIGMA_PX,
)
from .phases import DRAIN_SECONDS
from .phone import PHONE_CONNECTIONS, REQUEST_SECONDS, STREAM_READ_SECONDS, WAIT_SECONDS
from .run import Results
from .server import default_threads


def header(results: Results) -> str:
    """The title, the command and what it ran on: the set-up of the run."""
    setup, settings = results.setup, results.settings
    now = datetime.now().astimezone().isoformat(timespec="seconds")
    names = ("uvicorn", "fastapi", "starlette", "anyio", "h11", "httpx2", "sqlalchemy", "numpy")
    versions = ", ".join(f"{name} {version(name)}" for name in names)
    threads = asyncio.run(default_threads())
    code = source_state("backend", "shared_solver")
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
            f"- Code under test (backend, shared_solver): {code}",
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
            f"`httpx2.AsyncClient` (keep-alive, at most {PHONE_CONNECTIONS} connections, as a "
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
        '/landmarks/starter/n/crop`: "find #n"), pauses and sends its own landmarks #1..#n '
        "(`PUT /taps`: the answer is recomputed in the request). Each phone loads its "
        "overlay (`GET /overlay/<own role>`, JPEG) whenever its state shows a new answer; "
        "both phones wait until their state shows it; the seeker sends "
        "`DELETE`, and both streams must end with `expired`. Errors: any call that is not "
        "the expected 2xx or times out; a stream that drops, goes silent, or ends without "
        f"`expired`; a stream that never saw one of {', '.join(EXPECTED_EVENTS)}; a phone "
        f"that waited over {WAIT_SECONDS:g} s for what it expected."
    )
