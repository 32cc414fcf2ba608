"""Buddy Search load benchmark: two-phone searches at once through the production topology.

It starts the cluster of ``make run-cluster`` (``deploy/cluster.py``: nginx with TLS and
``deploy/nginx.conf`` -> 2 uvicorn replicas -> a throwaway PostgreSQL, all on loopback) and
runs Locust in this process against nginx's HTTPS address: ``--concurrency`` users, each a
pair of friends running searches back to back (``benchmarks/searches.py``), their first
starts spread over ``--ramp`` s, no search starting after ``--duration`` s, the searches
still running then finishing. It reports errors, p50/p95/p99 of every call (Locust's),
and the CPU (and memory) of each kind of process per completed search, read with psutil:
nginx, the replicas, PostgreSQL, and this load generator, which shares the machine; and
where the replicas' time goes, sampled by py-spy (``benchmarks/spy.py``).

    .venv/bin/python benchmarks/load.py [--concurrency N] [--duration S] [--ramp S]
        [--speed X] [--photo-side PX] [--suggestions] [--out PATH] [--stacks PATH]
                                                                        (make bench-load)

The report is printed and written as Markdown to ``docs/load-benchmark.md``.
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any

import gevent
import locust.env  # first of the third-party imports: Locust patches the standard library
import psutil
import psycopg
from crowd import Crowd
from report import (
    ROOT,
    command_line,
    heading,
    machine_cpu_seconds,
    markdown_table,
    ms,
    publish,
    quantiles,
    source_state,
    verdict,
)
from searches import APP_MS, DATABASE_MS, Search
from spy import RATE, Sampler

from backend.storage.database import database_url
from deploy.cluster import REPLICAS, Cluster, cluster
from deploy.nginx import binary
from deploy.postgres import PostgresServer

DEFAULT_OUT = ROOT / "docs" / "load-benchmark.md"
CONCURRENCY = 400
TARGET_P99_MS = 500.0  # every call but the photo upload
# CPU per completed search: a third of what the app took before its events carried what
# the phones show (352 ms of the replicas and 120 ms of PostgreSQL, issue 21).
TARGET_REPLICAS_MS = 120.0
TARGET_POSTGRESQL_MS = 60.0
UPLOAD = "PUT /photo"
DRAIN_SECONDS = 180.0  # searches still running at the end of the duration get this long
SAMPLE_SECONDS = 1.0
SEED = 20261121
KINDS = ("nginx", "replicas", "PostgreSQL", "load generator")
STATEMENTS = 8  # PostgreSQL's heaviest statements reported


@dataclass
class Processes:
    """The processes of each kind: CPU seconds so far, memory (PSS: shared pages split
    among their sharers, so PostgreSQL's shared buffers count once) sampled for its peak."""

    roots: dict[str, list[int]]
    peak_mb: dict[str, float] = field(default_factory=dict)

    def members(self, kind: str) -> list[psutil.Process]:
        found = []
        for pid in self.roots[kind]:
            try:
                root = psutil.Process(pid)
                # This process starts the cluster: its children are not the load generator.
                found += [root] if kind == "load generator" else [root, *root.children(True)]
            except psutil.NoSuchProcess:
                continue
        return found

    def cpu_seconds(self) -> dict[str, float]:
        """user + system of each kind's processes, and of their children that have exited
        (PostgreSQL's backends), since they started."""
        spent = {}
        for kind in KINDS:
            total = 0.0
            for process in self.members(kind):
                try:
                    times = process.cpu_times()
                except psutil.Error:
                    continue
                total += times.user + times.system
                if kind != "load generator":
                    total += times.children_user + times.children_system
            spent[kind] = total
        return spent

    def sample_memory(self) -> None:
        for kind in KINDS:
            total = 0.0
            for process in self.members(kind):
                try:
                    total += process.memory_full_info().pss / 2**20
                except psutil.Error:
                    continue
            self.peak_mb[kind] = max(self.peak_mb.get(kind, 0.0), total)


@dataclass
class Run:
    """What one run measured."""

    setup: argparse.Namespace
    stats: locust.stats.RequestStats
    cpu: dict[str, float]  # CPU seconds of each kind during the load
    machine_busy: float  # share of all cores busy during the load
    seconds: float  # from the first search's start to the last one's end
    memory_mb: dict[str, float]
    database: dict[str, float]  # peak size, WAL written (MB), connections opened
    statements: list[tuple[int, float, float, str]]  # PostgreSQL's heaviest
    versions: dict[str, str]
    cut_off: int
    sampler: Sampler  # where the replicas' time went


def postmaster(postgres: PostgresServer) -> int:
    return int((postgres.data / "postmaster.pid").read_text().split()[0])


class Database:
    """The cluster's database seen from here, on one connection of its own."""

    def __init__(self, url: str) -> None:
        conninfo = database_url(url).set(drivername="postgresql")
        self.connection = psycopg.connect(
            conninfo.render_as_string(hide_password=False), autocommit=True
        )
        self.version = str(self._one("SHOW server_version")).split()[0]
        self.connection.execute("CREATE EXTENSION IF NOT EXISTS pg_stat_statements")

    def statements_reset(self) -> None:
        self.connection.execute("SELECT pg_stat_statements_reset()")

    def statements(self, top: int) -> list[tuple[int, float, float, str]]:
        """The ``top`` statements by total time since the reset, this connection's aside:
        (calls, mean ms, total s, the statement's start)."""
        rows = self.connection.execute(
            "SELECT calls, mean_exec_time, total_exec_time / 1000, "
            "left(regexp_replace(query, '\\s+', ' ', 'g'), 70) FROM pg_stat_statements "
            "WHERE dbid = (SELECT oid FROM pg_database WHERE datname = current_database()) "
            "AND query NOT LIKE '%%pg_stat_statements%%' AND query NOT LIKE '%%pg_database_size%%' "
            "ORDER BY total_exec_time DESC LIMIT %s",
            (top,),
        ).fetchall()
        return [
            (int(calls), float(mean), float(total), str(text)) for calls, mean, total, text in rows
        ]

    def _one(self, query: str) -> Any:
        row = self.connection.execute(query).fetchone()
        return row[0] if row else None

    def size_mb(self) -> float:
        return float(self._one("SELECT pg_database_size(current_database())")) / 2**20

    def wal_mb(self) -> float:
        """Where the write-ahead log is: MB written since the server began."""
        return float(self._one("SELECT pg_wal_lsn_diff(pg_current_wal_lsn(), '0/0')")) / 2**20

    def connections(self) -> int:
        """Connections ever opened to the database (each a new backend, a password check)."""
        query = "SELECT sessions FROM pg_stat_database WHERE datname = current_database()"
        return int(self._one(query))


def load(
    setup: argparse.Namespace, running: Cluster, processes: Processes, sampler: Sampler
) -> Run:
    Search.crowd = Crowd.made(setup.photo_side, setup.seed)
    Search.authority = str(running.authority)
    Search.speed, Search.seed = setup.speed, setup.seed
    Search.suggestions = setup.suggestions
    environment = locust.env.Environment(user_classes=[Search], host=running.url)
    runner = environment.create_local_runner()
    database = Database(running.database_url)
    peak_mb = database.size_mb()

    sampling = True

    def sample() -> None:
        nonlocal peak_mb
        while sampling:
            processes.sample_memory()
            peak_mb = max(peak_mb, database.size_mb())
            gevent.sleep(SAMPLE_SECONDS)

    wal, connections = database.wal_mb(), database.connections()
    database.statements_reset()
    before, (busy, total) = processes.cpu_seconds(), machine_cpu_seconds()
    started = time.monotonic()
    Search.stop_at = started + setup.duration
    memory = gevent.spawn(sample)
    sampler.start()
    runner.start(setup.concurrency, spawn_rate=setup.concurrency / max(setup.ramp, 1e-3))
    gevent.sleep(setup.duration)
    while runner.user_count and time.monotonic() < Search.stop_at + DRAIN_SECONDS:
        gevent.sleep(0.5)
    cut_off = runner.user_count
    seconds = time.monotonic() - started
    after, (busy_after, total_after) = processes.cpu_seconds(), machine_cpu_seconds()
    sampler.stop()
    runner.quit()
    sampling = False  # not killed: its database connection must not be left mid-query
    memory.join()
    statements = database.statements(STATEMENTS)
    figures = {
        "size": peak_mb,
        "wal": database.wal_mb() - wal,
        "connections": database.connections() - connections,
    }
    return Run(
        setup,
        environment.stats,
        {kind: after[kind] - before[kind] for kind in KINDS},
        (busy_after - busy) / max(total_after - total, 1e-9),
        seconds,
        dict(processes.peak_mb),
        figures,
        statements,
        versions(database),
        cut_off,
        sampler,
    )


def versions(database: Database) -> dict[str, str]:
    nginx = subprocess.run([binary(), "-v"], capture_output=True, text=True, check=False)
    return {
        "nginx": nginx.stderr.strip().split("/")[-1],
        "PostgreSQL": database.version,
        **{name: metadata.version(name) for name in ("locust", "psutil", "uvicorn", "fastapi")},
    }


# --- the report ---------------------------------------------------------------------------


def server_percentiles(times_by_call: dict[str, list[float]], name: str) -> str:
    """p50 / p99 of a call's Server-Timing part: the app's own time (``APP_MS``) or its
    database statements' (``DATABASE_MS``). The rest of the phone's latency is queueing (in
    the replica before the app sees the request, nginx, the network, the load generator)."""
    times = times_by_call.get(name)
    return quantiles(times, (50, 99)) if times else ""


def header(run: Run) -> list[str]:
    setup, version = run.setup, run.versions
    photos = ", ".join(f"{len(photo) // 1000} KB" for photo in Search.crowd.photos)
    return [
        *heading("Load benchmark", "benchmarks/load.py", "bench-load"),
        f"- Machine: {platform.platform()}, {psutil.cpu_count()} cores,"
        f" {psutil.virtual_memory().total / 2**30:.0f} GB. Everything runs on it: nginx,"
        " the replicas, PostgreSQL and the load generator share these cores (and so does"
        ' whatever else runs there: below, "anything else").',
        f"- Code under test: {source_state('backend', 'shared_solver', 'deploy')}",
        f"- Topology (`make run-cluster`): nginx {version['nginx']} with `deploy/nginx.conf`"
        f" (TLS, the certificate made at start-up) -> {setup.replicas} uvicorn replicas"
        f" (uvicorn {version['uvicorn']}, FastAPI {version['fastapi']}) -> PostgreSQL"
        f" {version['PostgreSQL']} (a throwaway server, default settings), all on loopback.",
        f"- Load generator: Locust {version['locust']} in one process (gevent), over HTTPS to"
        " nginx, each phone with its own connections; CPU and memory read with psutil"
        f" {version['psutil']}.",
        f"- Load: {setup.concurrency} pairs of friends running searches back to back, both"
        f" event streams open; searches start for {setup.duration:g} s, the pairs' first ones"
        f" spread over {setup.ramp:g} s; those still running then get {DRAIN_SECONDS:g} s."
        f" People {setup.speed:g} times quicker than a brisk person (the pauses in"
        f" `benchmarks/searches.py`); photos {setup.photo_side} px wide ({photos} JPEG);"
        " 6 landmarks and the starter's mark of the joiner per search; "
        + (
            "the joiner asks for a suggested spot whenever the answer has a band for the"
            " landmark it finds, as the app does."
            if setup.suggestions
            else "no suggested spot asked for (the app asks for one per landmark found with"
            " an answer: `--suggestions`)."
        ),
    ]


def calls_table(calls: list[locust.stats.StatsEntry]) -> str:
    head = ["call", "calls", "failed", "p50 (ms)", "p95 (ms)", "p99 (ms)", "max (ms)"]
    return markdown_table(
        [*head, "in the app: p50 / p99 (ms)", "of which database: p50 / p99 (ms)"],
        [
            [
                f"`{entry.name}`",
                str(entry.num_requests),
                str(entry.num_failures),
                *(ms(entry.get_response_time_percentile(q)) for q in (0.5, 0.95, 0.99)),
                ms(entry.max_response_time),
                server_percentiles(APP_MS, entry.name),
                server_percentiles(DATABASE_MS, entry.name),
            ]
            for entry in calls
        ],
    )


def per_search_table(run: Run, calls: list[locust.stats.StatsEntry]) -> str:
    completed = Search.counts["completed"]
    searches = max(completed, 1)
    cores = {kind: run.cpu[kind] / run.seconds for kind in KINDS}
    others = max(run.machine_busy * (psutil.cpu_count() or 1) - sum(cores.values()), 0.0)
    durations = sorted(Search.durations) or [float("nan")]
    uploaded = sum(len(photo) for photo in Search.crowd.photos)
    downloaded = sum(entry.total_content_length for entry in calls) / searches
    kinds = " / ".join(KINDS)
    rows = {
        "searches started / completed": f"{Search.counts['started']} / {completed}",
        "completed per second": f"{completed / run.seconds:.2f} (over {run.seconds:.0f} s)",
        "search duration p50 / max (s)": (
            f"{durations[len(durations) // 2]:.1f} / {durations[-1]:.1f}"
        ),
        f"**CPU per completed search (ms): {kinds}**": " / ".join(
            f"**{1000 * run.cpu[kind] / searches:.0f}**" for kind in KINDS
        ),
        f"CPU over the run (cores): {kinds} / anything else": " / ".join(
            f"{cores[kind]:.2f}" for kind in KINDS
        )
        + f" / {others:.2f} (machine {100 * run.machine_busy:.0f} % busy)",
        f"peak memory (PSS, MB): {kinds}": " / ".join(
            f"{run.memory_mb.get(kind, 0):.0f}" for kind in KINDS
        ),
        "bytes per search: from the phones / to the phones (bodies)": (
            f"{uploaded / 1e6:.2f} MB / {downloaded / 1e6:.2f} MB"
        ),
        "PostgreSQL: peak database size / WAL written per search": (
            f"{run.database['size']:.0f} MB / {run.database['wal'] / searches:.1f} MB"
        ),
        "PostgreSQL connections opened during the run": f"{run.database['connections']:.0f}",
    }
    return markdown_table(["measured", "value"], list(rows.items()))


def spent(run: Run, per_search_ms: float) -> list[str]:
    """The replicas' busy samples (py-spy) by what they were doing, and that share of their
    CPU per search."""
    shares = run.sampler.shares
    total = sum(shares.values())
    if not total:
        return [f"Not sampled: {run.sampler.problem or 'no sample'}."]
    rows = [
        [what, f"{100 * count / total:.1f} %", f"{per_search_ms * count / total:.0f}"]
        for what, count in shares.most_common()
    ]
    cut = run.sampler.unreadable
    return [
        f"py-spy's samples of the replicas' busy threads ({total} at {run.sampler.rate} a"
        " second, over the run; py-spy leaves out idle ones, and so does this table where"
        " py-spy missed them: a thread waiting for sockets, for PostgreSQL or for work), by the"
        " route function on the stack (`<module>.<function>` of `backend/api/routes/`) or"
        " what else they were doing; that share of the replicas' CPU per search beside it."
        + (
            f" ({cut} lines of the recordings cut short as py-spy stopped: left out.)"
            if cut
            else ""
        ),
        "",
        markdown_table(["what", "share of samples", "ms per search"], rows),
    ]


def report(run: Run) -> str:
    stats = run.stats
    calls = sorted(
        (entry for entry in stats.entries.values() if entry.method != "FLOW"),
        key=lambda entry: entry.name,
    )
    failures = sum(entry.num_failures for entry in stats.entries.values())
    timed = [entry for entry in calls if entry.name != UPLOAD]
    worst = max(timed, key=lambda entry: entry.get_response_time_percentile(0.99))
    p99 = worst.get_response_time_percentile(0.99)
    errors = sorted(stats.errors.values(), key=lambda error: -error.occurrences)
    searches = max(Search.counts["completed"], 1)
    replicas, postgresql = (1000 * run.cpu[kind] / searches for kind in ("replicas", "PostgreSQL"))
    return "\n".join(
        [
            *header(run),
            "",
            "## Targets",
            "",
            f"- {verdict(failures == 0 and not run.cut_off)}: 0 errors ({failures} failed calls"
            f" and flow errors; {run.cut_off} searches cut off by the time limit)",
            f"- {verdict(p99 <= TARGET_P99_MS)}: p99 at most {TARGET_P99_MS:g} ms for every call"
            f" but the photo upload (slowest: `{worst.name}` {ms(p99)} ms)",
            f"- {verdict(replicas <= TARGET_REPLICAS_MS)}: replica CPU per search at most"
            f" {TARGET_REPLICAS_MS:g} ms ({replicas:.0f} ms)",
            f"- {verdict(postgresql <= TARGET_POSTGRESQL_MS)}: PostgreSQL CPU per search at most"
            f" {TARGET_POSTGRESQL_MS:g} ms ({postgresql:.0f} ms)",
            "",
            "## Calls",
            "",
            "Latency is the phone's (Locust's): request sent to answer read, for the event"
            " stream to its first byte; Locust keeps times above 100 ms to 2 significant"
            ' figures. "In the app" is the app\'s own time (its Server-Timing): the rest is'
            " waiting (for the replica's event loop, threads and database connections),"
            ' nginx, the network and the load generator. "Of which database" is the time'
            " of its database statements (sent, run, answer read); the rest of the app's"
            " time is its own work and its waits for a worker thread, the GIL and a"
            " connection.",
            "",
            calls_table(calls),
            "",
            "## Per search",
            "",
            per_search_table(run, calls),
            "",
            "## Where the replicas' time goes",
            "",
            *spent(run, replicas),
            "",
            "## PostgreSQL's heaviest statements",
            "",
            "By total time in PostgreSQL during the run (pg_stat_statements), waits for locks"
            " included. `VACUUM (FULL)` is the erase of deleted rows' bytes (one replica for"
            " all, after deletions, at most every `BUDDY_ERASE_INTERVAL_SECONDS`): it locks"
            " each table while copying it.",
            "",
            markdown_table(
                ["statement", "calls", "mean (ms)", "total (s)"],
                [
                    [f"`{text}`", str(calls), ms(mean), f"{total:.2f}"]
                    for calls, mean, total, text in run.statements
                ],
            ),
            "",
            "## Errors",
            "",
            *[f"- {error.occurrences} x {error.name}: {error.error}" for error in errors],
            *([] if errors else ["None."]),
            "",
        ]
    )


def main(argv: Sequence[str] | None = None) -> None:
    parser = command_line(__doc__, DEFAULT_OUT)
    option = parser.add_argument
    option("--concurrency", type=int, default=CONCURRENCY, help="pairs at once (%(default)s)")
    option("--duration", type=float, default=120.0, help="s during which searches start")
    option("--ramp", type=float, default=30.0, help="s over which the pairs start")
    option("--speed", type=float, default=1.0, help="people this many times quicker")
    option("--photo-side", type=int, default=1600, help="the photos' long side, px")
    option("--seed", type=int, default=SEED)
    option("--replicas", type=int, default=REPLICAS, choices=range(1, 9), help="(%(default)s)")
    option(
        "--suggestions",
        action="store_true",
        help="the joiner also asks for a suggested spot, as the app does (not in the targets' "
        "search: the issue's baseline had none)",
    )
    option(
        "--sample-rate",
        type=int,
        default=RATE,
        help="py-spy's samples a second of each replica (%(default)s; 0: none, to see what "
        "sampling costs)",
    )
    option(
        "--stacks",
        type=Path,
        help="also write the replicas' sampled stacks there, collapsed (for a flame graph)",
    )
    setup = parser.parse_args(argv)
    if not (1 <= setup.concurrency <= 2000 and 0 < setup.duration <= 3600):
        parser.error("--concurrency must be in [1, 2000], --duration in (0, 3600]")
    if not (0 <= setup.ramp <= setup.duration and 0.1 <= setup.speed <= 1000):
        parser.error("--ramp must be in [0, duration], --speed in [0.1, 1000]")
    if not 0 <= setup.sample_rate <= 1000:
        parser.error("--sample-rate must be in [0, 1000]")
    with tempfile.TemporaryDirectory(prefix="buddy-load-") as folder:
        # pg_stat_statements: what PostgreSQL's time goes to (the erase among it).
        postgres = PostgresServer({"shared_preload_libraries": "pg_stat_statements"})
        try:
            postgres.start()
            url = postgres.url(postgres.create_database(name="buddy"))
            with cluster(Path(folder), url, replicas=setup.replicas) as running:
                replicas = [replica.pid for replica in running.replicas]
                processes = Processes(
                    {
                        "nginx": [running.nginx.pid],
                        "replicas": replicas,
                        "PostgreSQL": [postmaster(postgres)],
                        "load generator": [os.getpid()],
                    }
                )
                sampler = Sampler(replicas, Path(folder), setup.sample_rate)
                run = load(setup, running, processes, sampler)
        finally:
            postgres.remove()
    if setup.stacks is not None:
        run.sampler.write_stacks(setup.stacks)
    publish(report(run), setup.out)


if __name__ == "__main__":
    main()
