"""A benchmark run as its make target runs it: a script of ``benchmarks/`` in a subprocess
from the repository root (Locust patches the standard library of its process)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def run_benchmark(name: str, *options: str, out: Path, timeout: float) -> tuple[str, str]:
    """``benchmarks/<name>.py`` with ``options`` and ``--out out``: what it printed and the
    report it wrote. Fails unless it exits cleanly within ``timeout`` s (beyond it hangs)."""
    script = ROOT / "benchmarks" / f"{name}.py"
    done = subprocess.run(
        [sys.executable, str(script), *options, "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-4000:]
    return done.stdout, out.read_text()
