"""The tap-precision benchmark (``benchmarks/taps.py``) at a small scale, in a subprocess as
``make bench-taps`` runs it: two phones in Chromium play real searches through the app.

Asserted, because it is the point of the app's rule and deterministic for the seeds: the
regions drawn from each tap's own precision hold the truth far more often than those of one
fixed 3 px for every tap (ten searches: at least 7 of 10, against a 95 % level)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "taps.py"


def test_the_apps_tap_precision_gives_honest_regions(tmp_path: Path) -> None:
    out = tmp_path / "tap-precision.md"
    done = subprocess.run(
        [sys.executable, str(SCRIPT), "--trials", "10", "--out", str(out)],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
        timeout=600,
    )
    held = json.loads(done.stdout.strip().splitlines()[-1])
    text = out.read_text()
    assert text.startswith("# Tap precision through the app")
    assert "| the app's (each tap's own, docs/app.md) |" in text
    app, fixed = held["app"], held["fixed"]
    assert app["claimed"] >= 9
    assert app["held"] >= 0.7 * app["claimed"]
    assert app["held"] / app["claimed"] > fixed["held"] / max(fixed["claimed"], 1)
