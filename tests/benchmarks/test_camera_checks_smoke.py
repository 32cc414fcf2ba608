"""The camera-model checks (``benchmarks/camera_checks.py``) at a tiny scale, in a subprocess
as ``make bench-camera`` runs them: they exit cleanly and the report has every section with
a row for every variant. No figure is asserted: a handful of trials measure nothing."""

from __future__ import annotations

from pathlib import Path

from benchmark_scripts import assert_report_has, run_benchmark


def test_camera_checks_run_and_report_every_section(tmp_path: Path) -> None:
    _, text = run_benchmark("camera_checks", "--trials", "3", folder=tmp_path, timeout=120)
    sections = """
        ## 1. The focal-length prior
        ## 2. The principal point at the centre
        ## 3. Landmarks on one plane
        ## 4. The bootstrap where redundancy is low
        ## 5. Ranking exact roots with the camera unknown
    """
    assert_report_has(text, sections=sections)
    rows = [line for line in text.splitlines() if line.startswith("| ") and "---" not in line]
    # Header rows excluded: 20 prior rows, 10 edited photos, 6 floor rows, 6 bootstrap rows,
    # 8 ranking rows.
    assert (
        len([r for r in rows if not r.startswith("| taps") and not r.startswith("| scenes")]) == 50
    )
    assert "broad (the phone prior)" in text
    assert "stretched 30 % sideways" in text
    assert "first version" in text
