"""The network benchmark (``benchmarks/network.py``) at its smallest, in a subprocess as
``make bench-network`` runs it: one search per profile, two phones in Chromium on a live
server. It exits cleanly, and its report has a row for each phone on each profile, the
answer's rows, the bytes by kind and every target. No time or byte count is asserted: one
search measures nothing."""

from __future__ import annotations

from pathlib import Path

import pytest
from benchmark_scripts import run_benchmark

# Mostly waiting on the throttled link (make test runs it in a lane of its own).
pytestmark = pytest.mark.waits

HUNG_SECONDS = 300  # one search per profile takes about 30 s: beyond this it hangs


def test_network_benchmark_runs_both_profiles_and_reports(tmp_path: Path) -> None:
    printed, report = run_benchmark("network", "--runs", "1", folder=tmp_path, timeout=HUNG_SECONDS)
    assert report == printed.split("{", 1)[0]  # printed, then the JSON summary line
    for profile in ("loopback", "venue"):
        for phone in ("starter (Pixel 7)", "joiner (iPhone 13)"):
            assert f"| {profile} | {phone} | " in report
            assert f"{profile}, {phone}: photo chosen -> tappable" in report
            assert f"{profile}, {phone}: a whole search" in report
        assert f"| {profile} | joiner: last tap -> answer | text " in report
        assert f"{profile}: last tap -> answer drawn on the other phone" in report
    assert "1.5 Mbit/s up, 3 Mbit/s down, 300 ms round trip" in report
    assert "Received bytes by what was fetched" in report
    assert "| app |" in report
