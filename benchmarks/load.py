"""Buddy Search load benchmark: many two-phone sessions at once, event streams open, one run.

One real uvicorn (``backend.main:app``; one worker unless ``--workers``; a new SQLite
database in a temporary folder unless ``--database postgresql``), started by this script on
a free loopback port and stopped at the end. An asyncio driver plays both phones of every
session as the phone app does, each phone with its own ``httpx2.AsyncClient`` (keep-alive):

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
        [--event-poll-seconds S] [--quiet-sessions K] [--out PATH]     (``make bench-load``)

The report is printed and written as Markdown to ``docs/load-benchmark.md``.

A quick run, to see that it all works (the smoke test's, in tests/benchmarks): ``--concurrency
3 --duration 5 --speed 50 --idle-seconds 1 --event-poll-seconds 1 --quiet-sessions 1 --out
PATH``; ``--event-poll-seconds`` also shortens the costs phase, which waits one poll interval
for the server to notice the closed streams.

This file is the command: its options, then the run and the report. The parts are in
``benchmarks/crowd/`` (its ``__init__`` lists them).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from crowd.options import Setup
from crowd.run import run
from crowd.sections import report
from report import ROOT, publish

DEFAULT_OUT = ROOT / "docs" / "load-benchmark.md"
DEFAULT_CONCURRENCY = 200
DEFAULT_DURATION = 120.0
DEFAULT_RAMP = 30.0  # slot i starts its first session at i / N of this: no thundering herd
DEFAULT_IDLE_SECONDS = 10.0
DEFAULT_SPEED = 1.0
DEFAULT_QUIET_SESSIONS = 5
SEED = 20261121


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
        "--quiet-sessions",
        type=int,
        default=DEFAULT_QUIET_SESSIONS,
        help="sessions run one at a time on the quiet server (default %(default)s)",
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
    if not 1 <= args.quiet_sessions <= 100:
        parser.error("--quiet-sessions must be in [1, 100]")
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
        quiet_sessions=args.quiet_sessions,
        speed=args.speed,
        workers=args.workers,
        database_kind=args.database,
        event_poll_seconds=args.event_poll_seconds,
        seed=args.seed,
    )
    publish(report(run(setup)), args.out)


if __name__ == "__main__":
    main()
