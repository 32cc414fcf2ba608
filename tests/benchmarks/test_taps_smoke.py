"""The tap-precision benchmark (``benchmarks/taps.py``) at a small scale, in a subprocess as
``make bench-taps`` runs it: two phones in Chromium play real searches through the app.

Asserted, because it is the point of the app's rule and deterministic for the seeds: the
regions drawn from each tap's own precision hold the truth far more often than those of one
fixed 3 px for every tap (six searches: at least 70 %, against a 95 % level)."""

from __future__ import annotations

import json
from pathlib import Path

from benchmark_scripts import run_benchmark


def test_the_apps_tap_precision_gives_honest_regions(tmp_path: Path) -> None:
    printed, text = run_benchmark("taps", "--trials", "6", folder=tmp_path, timeout=600)
    held = json.loads(printed.strip().splitlines()[-1])
    assert text.startswith("# Tap precision through the app")
    assert "| the app's (each tap's own, docs/app.md) |" in text
    app, fixed = held["app"], held["fixed"]
    assert app["claimed"] >= 5
    assert app["held"] >= 0.7 * app["claimed"]
    assert app["held"] / app["claimed"] > fixed["held"] / max(fixed["claimed"], 1)
