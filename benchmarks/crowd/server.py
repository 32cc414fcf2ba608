"""The server under load: its processes, their CPU and memory (/proc, so no psutil), and
its database."""

from __future__ import annotations

import importlib.util
import os
import re
import sqlite3
from collections.abc import Iterator
from contextlib import closing, contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path

import anyio.to_thread
from report import ROOT, CpuSnapshot

from backend.storage.database import connect

CORES = os.cpu_count() or 1


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


def peak_memory_mb(pid: int) -> float:
    """VmHWM of ``pid``: the most resident memory it has had, MB."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return 0.0
    found = re.search(r"^VmHWM:\s+(\d+) kB", status, re.M)
    return int(found.group(1)) / 1024 if found else 0.0


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


async def default_threads() -> int:
    """anyio's worker threads, for sync endpoints and the streams' reads: how many by default."""
    return int(anyio.to_thread.current_default_thread_limiter().total_tokens)
