"""The load benchmark (``benchmarks/load.py``) end to end at a tiny scale, in a subprocess as
``make bench-load`` runs it (Locust patches the standard library of its process): it
starts the cluster (nginx, 2 replicas, PostgreSQL), exits cleanly, writes its report, and
every search it started completed without an error. No timing is asserted."""

from __future__ import annotations

import re
from pathlib import Path

from benchmark_scripts import run_benchmark

# 3 pairs of friends, 50 times quicker than people, starting searches for 8 s.
TINY = ["--concurrency", "3", "--duration", "8", "--ramp", "1", "--speed", "50"]
HUNG_SECONDS = 120  # a run this small takes about 25 s: beyond this it hangs


def found(pattern: str, text: str) -> tuple[str, ...]:
    match = re.search(pattern, text)
    assert match is not None, f"{pattern!r} not in the report:\n{text}"
    return match.groups()


def test_load_benchmark_runs_every_search_through_the_cluster(tmp_path: Path) -> None:
    printed, report = run_benchmark("load", *TINY, folder=tmp_path, timeout=HUNG_SECONDS)
    assert printed == report  # printed and written alike
    sections = ("# Load benchmark", "## Targets", "## Calls", "## Per search", "## Errors")
    for section in (*sections, "## Where the replicas' time goes"):
        assert f"\n{section}\n" in f"\n{report}", section

    started, completed = found(r"\| searches started / completed \| (\d+) / (\d+) \|", report)
    assert int(started) >= 3  # each pair starts one at least
    assert completed == started
    assert found(r"- (\w+): 0 errors \((\d+) failed", report) == ("PASS", "0")
    assert "\n## Errors\n\nNone.\n" in report
    # Every call of a search was made and counted, through nginx.
    for call in ("POST /api/sessions", "GET /events (first byte)", "PUT /photo", "PUT /taps"):
        calls, failed = found(rf"\| `{re.escape(call)}` \| (\d+) \| (\d+) \|", report)
        assert int(calls) >= int(started)
        assert failed == "0"
    # Each kind of process was measured: nginx, the replicas, PostgreSQL, the load generator.
    (row,) = [line for line in report.splitlines() if "CPU per completed search" in line]
    cpu = [float(value) for value in re.findall(r"\*\*([\d.]+)\*\*", row)]
    assert len(cpu) == 4
    assert all(value > 0 for value in cpu)
