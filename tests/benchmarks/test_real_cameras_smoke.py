"""The real-camera measurement (``benchmarks/real_cameras.py``) at a tiny scale, in a
subprocess as it is run: it exits cleanly, ``solve`` raised nothing but ``SolverError`` on any
real pair, and the report has every section with a row for every pair. No figure is asserted:
one trial measures nothing."""

from __future__ import annotations

from pathlib import Path

from benchmark_scripts import assert_report_has, run_benchmark, targets_of

from testbed.real_cameras import load_pairs

SECTIONS = """
    ## Targets
    ## 1. The pairs
    ## 2. Friend 1 in or near photo 2
    ## 3. Friend 1 outside photo 2
    ## 4. Photo 2 zoomed
    ## 5. More landmarks never worse?
    ## 6. Reference
"""


def test_real_cameras_run_and_report_every_section(tmp_path: Path) -> None:
    _, text = run_benchmark("real_cameras", "--trials", "1", folder=tmp_path, timeout=300)
    assert_report_has(text, sections=SECTIONS)
    assert "Crashes (exceptions other than SolverError): 0." in text
    for pair in load_pairs():
        assert f"| {pair.set_name} | {pair.camera_ids[0]} -> {pair.camera_ids[1]} |" in text
    assert "OpenCV 8-point" in text
    lines = targets_of(text, end="## 1.")
    assert [line.split(":", 1)[0] in ("- PASS", "- FAIL") for line in lines] == [True] * 3
    for expected in ("a landmark more never", "camera model is kept", "never gets a confident"):
        assert any(expected in line for line in lines), expected
