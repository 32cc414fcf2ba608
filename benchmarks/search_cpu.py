"""CPU per search, by route, in one process: a small, repeatable stand-in for the replicas'
share of ``make bench-load`` (``benchmarks/load.py``), for profiling and before/after runs.

The app (``backend.main:app``'s ``create_app``) runs in this process on SQLite in a
temporary folder (``--database URL``: another one, e.g. a throwaway PostgreSQL's), behind
FastAPI's TestClient. Each of ``--searches`` searches plays the calls of
``benchmarks/searches.py`` with its photos and taps (``benchmarks/crowd.py``), without its
pauses and without event streams: create, join, each phone reads the state, uploads its
photo; the starter marks the joiner and taps 6 landmarks one PUT at a time; for each, the
joiner loads its crop and taps its own; the starter deletes the search. The load
benchmark's phones read the state when an event cannot be taken in; here each phone reads it
once at the start and once at the end.

Each call is timed with ``time.process_time`` less the calling thread's ``time.thread_time``:
the CPU of the app's threads (the TestClient's event loop, the app's worker threads), not the
client's, and no other work on the machine (though a busy machine slows everything a little:
compare runs made at the same time); the first search (imports, caches, the first
statements) is left out. The TestClient's way into the app costs more than uvicorn's: a
call that does nothing (``GET /api/version``) takes ~3.7 ms of the app's CPU here, against
~1.5 ms per call for "HTTP around the calls" in ``make bench-load``'s report. Printed:
CPU ms per search by route (the sum of its calls) and per call, over ``--rounds`` rounds
(each on a fresh database), median and spread.

    PYTHONPATH=. .venv/bin/python benchmarks/search_cpu.py [--searches N] [--rounds R]

``PYTHONPATH=.``: this checkout's code first, before any other the virtualenv names (a
worktree sharing another checkout's virtualenv would measure that checkout's code; the
script refuses to).

``--profile PATH``: cProfile of the measured searches, written to PATH (pstats).
"""

from __future__ import annotations

import argparse
import cProfile
import random
import statistics
import tempfile
import time
from collections import defaultdict
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from crowd import LANDMARKS, Crowd
from fastapi.testclient import TestClient
from report import ROOT, markdown_table

import backend
from backend.main import create_app
from backend.settings import Settings
from testbed.client import Phone, start

PHOTO_SIDE = 1600  # as benchmarks/load.py sends them
SEED = 1


class Meter:
    """CPU seconds per route name, summed over the calls measured."""

    def __init__(self) -> None:
        self.seconds: defaultdict[str, float] = defaultdict(float)
        self.calls: defaultdict[str, int] = defaultdict(int)
        self.on = False

    @contextmanager
    def measure(self, name: str) -> Iterator[None]:
        """The app's CPU during the call: the process's less this thread's, the client's
        (the TestClient's requests and answers: as much as the app's own work at times)."""
        start, client = time.process_time(), time.thread_time()
        try:
            yield
        finally:
            if self.on:
                spent = time.process_time() - start - (time.thread_time() - client)
                self.seconds[name] += spent
                self.calls[name] += 1


def search(client: TestClient, crowd: Crowd, rng: random.Random, meter: Meter) -> None:
    """One search, as benchmarks/searches.py plays it (no pauses, no streams)."""
    starter_taps, joiner_taps, mark = crowd.taps(rng)
    with meter.measure("POST /api/sessions"):
        starter, code = start(client)
    with meter.measure("POST /api/sessions/join"):
        joined = client.post("/api/sessions/join", json={"code": code})
    joiner = Phone(client, starter.session_id, joined.raise_for_status().json()["token"], "joiner")
    phones = (starter, joiner)

    def call(phone: Phone, name: str, method: str, rest: str = "", **options: Any) -> Any:
        """``phone``'s call, measured as ``name``: its JSON, if any (fails on an error)."""
        with meter.measure(name):
            answer = phone.ok(method, rest, **options)
        json = answer.headers.get("content-type", "").startswith("application/json")
        return answer.json() if json else None

    for phone in phones:
        call(phone, "GET /api/sessions/{id}", "GET")
    for phone, photo in zip(phones, crowd.photos, strict=True):
        files = {"photo": ("photo.jpg", photo, "image/jpeg")}
        call(phone, "PUT /photo", "PUT", "/photo", files=files)
    for n in range(1, LANDMARKS + 1):
        body = {"landmarks": starter_taps[:n], "friend": mark}
        state = call(starter, "PUT /taps", "PUT", "/taps", json=body)
        seen = next(t for t in state["taps"]["starter"]["landmarks"] if t["id"] == n)
        # The crop as the app loads it: an image, its token in the query (no header).
        query = {"token": joiner.token, "v": f"{seen['x']},{seen['y']}"}
        with meter.measure("GET /landmarks/starter/{n}/crop"):
            crop = client.get(joiner.url(f"/landmarks/starter/{n}/crop"), params=query)
        if crop.status_code != 200:
            raise RuntimeError(f"crop #{n}: {crop.status_code} {crop.text[:300]}")
        call(joiner, "PUT /taps", "PUT", "/taps", json={"landmarks": joiner_taps[:n]})
    for phone in phones:
        final = call(phone, "GET /api/sessions/{id}", "GET")
    if final.get("answer") is None:
        raise RuntimeError("no answer after the last taps")
    call(starter, "DELETE /api/sessions/{id}", "DELETE", expect=204)


def round_of(
    searches: int, crowd: Crowd, database: str | None, profile: cProfile.Profile | None
) -> Meter:
    """One round on a fresh database: a warm-up search, then ``searches`` measured."""
    meter = Meter()
    with tempfile.TemporaryDirectory() as folder:
        url = database or f"sqlite:///{Path(folder) / 'buddy.db'}"
        app = create_app(Settings(database_url=url, sweep_interval_seconds=3600))
        with TestClient(app, raise_server_exceptions=True) as client:
            rng = random.Random(SEED)
            search(client, crowd, rng, meter)  # warm-up
            meter.on = True
            if profile is not None:
                profile.enable()
            for _ in range(searches):
                search(client, crowd, rng, meter)
            if profile is not None:
                profile.disable()
    return meter


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--searches", type=int, default=20)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--database", help="a database URL (default: SQLite in a temp folder)")
    parser.add_argument("--profile", type=Path, help="write a cProfile of the searches here")
    args = parser.parse_args()
    measured = Path(backend.__file__).resolve()
    if not measured.is_relative_to(ROOT.resolve()):
        parser.error(f"this would measure {measured.parent}, not {ROOT}: run with PYTHONPATH=.")
    crowd = Crowd.made(PHOTO_SIDE, SEED)
    profile = cProfile.Profile() if args.profile else None
    rounds = [round_of(args.searches, crowd, args.database, profile) for _ in range(args.rounds)]
    if profile is not None:
        profile.dump_stats(str(args.profile))
    names = sorted({name for meter in rounds for name in meter.seconds})
    print(
        f"CPU per search, ms ({args.searches} searches x {args.rounds} rounds;"
        " median [min-max] over rounds)"
    )
    rows = []
    for name in sorted(names, key=lambda n: -statistics.median(m.seconds[n] for m in rounds)):
        per = [1000 * m.seconds[name] / args.searches for m in rounds]
        calls = rounds[0].calls[name] / args.searches
        spread = f"{statistics.median(per):.1f} [{min(per):.1f}-{max(per):.1f}]"
        rows.append([f"`{name}`", f"{calls:g}", spread, f"{statistics.median(per) / calls:.2f}"])
    totals = [1000 * sum(m.seconds.values()) / args.searches for m in rounds]
    spread = f"**{statistics.median(totals):.1f}** [{min(totals):.1f}-{max(totals):.1f}]"
    rows.append(["**all**", "", spread, ""])
    print(markdown_table(["route", "calls per search", "ms per search", "ms per call"], rows))


if __name__ == "__main__":
    main()
