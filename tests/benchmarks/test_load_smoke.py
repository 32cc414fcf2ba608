"""The load benchmark (``benchmarks/load.py``) end to end at a tiny scale, in a subprocess as
``make bench-load`` runs it: it exits cleanly, writes its report, and every session it
started completed without an error. No timing is asserted."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "load.py"
# Every phase short: 3 sessions at once for 5 s, people 50 times quicker, one session on
# the quiet server, 1 s of idle streams, and a 1 s event poll (the costs phase waits one
# poll interval for the server to notice the streams it closed).
TINY = [
    "--concurrency",
    "3",
    "--duration",
    "5",
    "--speed",
    "50",
    "--quiet-sessions",
    "1",
    "--idle-seconds",
    "1",
    "--event-poll-seconds",
    "1",
]
HUNG_SECONDS = 80  # a run this small takes about 20 s: beyond this it hangs


def found(pattern: str, text: str) -> tuple[str, ...]:
    match = re.search(pattern, text)
    assert match is not None, f"{pattern!r} not in the report:\n{text}"
    return match.groups()


def test_load_benchmark_runs_and_completes_every_session(tmp_path: Path) -> None:
    out = tmp_path / "load-benchmark.md"
    done = subprocess.run(
        [sys.executable, str(SCRIPT), *TINY, "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=HUNG_SECONDS,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-4000:]
    report = out.read_text()
    assert done.stdout == report  # printed and written alike
    for section in ("# Load benchmark", "## Targets", "## Under load", "## Quiet server"):
        assert f"\n{section}\n" in f"\n{report}", section

    started, completed = found(r"\| sessions started / completed \| (\d+) / (\d+) \|", report)
    assert int(started) >= 3  # each slot starts one at least
    assert completed == started
    failed, flow, incomplete = found(
        r"- PASS: 0 errors \((\d+) failed calls, (\d+) flow errors; (\d+) of \d+ sessions", report
    )
    assert (failed, flow, incomplete) == ("0", "0", "0")

    quiet_completed, quiet_errors = found(r"Sessions completed: (\d+); errors: (\d+);", report)
    assert (quiet_completed, quiet_errors) == ("1", "0")
    assert found(r"Idle streams: .*; errors: (\d+)\.", report) == ("0",)
    assert found(r"Failed calls while measuring: (\d+)\.", report) == ("0",)
