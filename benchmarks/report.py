"""What the benchmarks share: their Markdown and figures, what they say of the machine, the
server and the code under test, and how they time and publish a run."""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import platform
import shlex
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import datetime
from pathlib import Path
from typing import TypeVar

import httpx2
import numpy as np
import psutil

from testbed.client import server_timing

ROOT = Path(__file__).resolve().parent.parent

T = TypeVar("T")


# --- Markdown and figures ----------------------------------------------------------------------


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def verdict(passed: bool) -> str:
    return "PASS" if passed else "FAIL"


def targets_section(checks: Sequence[tuple[str, bool]]) -> list[str]:
    """A report's closing "## Targets" lines: each (what, passed) as "- PASS: what"."""
    return ["## Targets", "", *(f"- {verdict(passed)}: {what}" for what, passed in checks)]


def percent(fraction: float) -> str:
    return f"{100 * fraction:.0f} %"


def percentile(values: Sequence[float], q: float) -> float:
    """numpy's percentile (linear interpolation) of ``values``; NaN when there are none."""
    if not values:
        return float("nan")
    return float(np.percentile(np.asarray(values, dtype=np.float64), q))


def quantiles(
    values: Sequence[float], qs: Sequence[float], show: Callable[[float], str] | None = None
) -> str:
    """The :func:`percentile` of ``values`` at each of ``qs`` (100: the largest), written by
    ``show`` (default :func:`ms`), " / " between them."""
    return " / ".join((show or ms)(percentile(values, q)) for q in qs)


def nearest_rank(values: Sequence[float], q: float) -> float:
    """The nearest-rank percentile (a value that occurred): safe with inf (no answer)."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, math.ceil(q / 100 * len(ordered)) - 1))]


def ms(value: float) -> str:
    """A time in ms to about 3 significant figures; "-" when nothing was measured (NaN)."""
    if math.isnan(value):
        return "-"
    return f"{value:.2f}" if value < 10 else f"{value:.1f}" if value < 100 else f"{value:.0f}"


def in_ms(value: float) -> str:
    """A time in ms, to the ms, with its unit."""
    return f"{value:.0f} ms"


def in_s(value: float) -> str:
    """A time in ms, in s to the hundredth, with its unit."""
    return f"{value / 1000:.2f} s"


# --- the machine and the server ----------------------------------------------------------------


def machine_cpu_seconds() -> tuple[float, float]:
    """(busy, total) CPU seconds of all cores since boot; idle and iowait are not busy
    (guest time is counted in user time)."""
    times = psutil.cpu_times()
    total = sum(times) - times.guest - times.guest_nice
    return total - times.idle - times.iowait, total


def process_cpu_seconds(pid: int) -> float:
    """user + system CPU seconds of every thread of ``pid``; 0 once it is gone."""
    try:
        times = psutil.Process(pid).cpu_times()
    except psutil.Error:
        return 0.0
    return times.user + times.system


@dataclass(frozen=True)
class CpuSnapshot:
    """Cumulative CPU seconds at one instant: the server (all its processes), this process,
    the machine."""

    at: float  # time.monotonic()
    server: float
    client: float
    machine_busy: float
    machine_total: float


def cpu_snapshot(server_pids: Sequence[int]) -> CpuSnapshot:
    busy, total = machine_cpu_seconds()
    server = sum(process_cpu_seconds(pid) for pid in server_pids)
    return CpuSnapshot(time.monotonic(), server, time.process_time(), busy, total)


def server_timing_ms(response: httpx2.Response) -> float:
    """The ``app`` part of the response's Server-Timing header, ms."""
    return server_timing(response.headers["server-timing"])["app"]


def machine(extra: str = "") -> str:
    """A report's line on the machine that ran it, ``extra`` appended."""
    return (
        f"- Machine: {platform.platform()}, {platform.machine()}, "
        f"os.cpu_count() = {os.cpu_count()}{extra}"
    )


def uvicorn_stack() -> str:
    """What uvicorn's defaults (``--loop auto --http auto``) pick in this environment."""
    loop = "uvloop" if importlib.util.find_spec("uvloop") else "asyncio (uvloop not installed)"
    http = "httptools" if importlib.util.find_spec("httptools") else "h11 (httptools not installed)"
    return f"event loop {loop}, HTTP parser {http}"


# --- the code under test -------------------------------------------------------------------


def git(*args: str) -> str:
    return subprocess.run(
        ["git", *args], cwd=ROOT, capture_output=True, text=True, check=True, timeout=30
    ).stdout


def source_state(*paths: str) -> str:
    """The commit, and any uncommitted changes under ``paths``: the code under test."""
    try:
        commit = git("rev-parse", "--short", "HEAD").strip()
        changed = git("status", "--porcelain", "--", *paths).splitlines()
    except (OSError, subprocess.CalledProcessError, subprocess.TimeoutExpired):
        return "not a git checkout"
    files = [line[3:] for line in changed if line.strip()]
    return f"commit {commit}" + (
        f", uncommitted changes in {', '.join(files)}" if files else ", no uncommitted changes"
    )


# --- running a benchmark ---------------------------------------------------------------------


def heading(title: str, script: str, make_target: str) -> list[str]:
    """A report's first lines: its title, the command that wrote it (``script`` with this
    run's arguments, and its make target) and the date."""
    return [
        f"# {title}",
        "",
        f"Command: `{shlex.join(['python', script, *sys.argv[1:]])}` "
        f"(from the repository root, in its virtualenv; `make {make_target}`)",
        "",
        f"- Date: {datetime.now().astimezone().isoformat(timespec='seconds')}",
    ]


def command_line(doc: str | None, out: Path) -> argparse.ArgumentParser:
    """A benchmark's options: described by its docstring's first paragraph, with ``--out``
    (default ``out``), the report's path."""
    parser = argparse.ArgumentParser(description=(doc or "").split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=out, help="Markdown report path")
    return parser


def log(message: str) -> None:
    """Progress, on stderr: stdout is the report."""
    print(message, file=sys.stderr, flush=True)


def timed(seconds: dict[str, float], name: str, work: Callable[[], T]) -> T:
    """``work()``, its wall time kept as ``seconds[name]``."""
    log(f"[{name}] ...")
    start = time.perf_counter()
    result = work()
    seconds[name] = time.perf_counter() - start
    return result


def publish(text: str, out: Path) -> None:
    """The report, printed and written to ``out``."""
    print(text, end="")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
