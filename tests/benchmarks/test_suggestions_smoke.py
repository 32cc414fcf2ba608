"""The suggestion benchmark (``benchmarks/suggestions.py``) at a tiny scale, in a subprocess as
``make bench-suggest`` runs it: it exits cleanly, and the report has every section, every
table's rows and the targets. No figure and no timing is asserted: three scenes measure
nothing."""

from __future__ import annotations

import re
from pathlib import Path

from benchmark_scripts import assert_report_has, run_benchmark, targets_of

TINY = "--calibration 1 --evaluation 1 --compare 1 --arena-calibration 0 --arena-evaluation 1"
SECTIONS = """
    ## 1. The rendered venues
    ## 2. The band
    ## 3. Suggestions in the halls
    ## 4. Suggestions in the arenas, held out
    ## 5. Choosing the rule
    ## 6. Against SIFT in the band, and without colour
    ## 7. The tap check
    ## 8. Time
    ## Targets
"""
ROWS = """
    | evaluation |
    | 5 landmarks + friend 2 |
    | every landmark |
    | tapped in photo 2 |
    | 3 | 8 px |
    | **all** |
    | now, without the context (the rule before it) |
    | now (the rule in the code) |
    | 0.7 |
    | 0.1 |
    | none (as read alone) |
    | least score in context | lead 0.05 |
    | template matching in epipolar coordinates, colour (the rule above) |
    | SIFT in the band, 2+ keypoints agreeing |
    | 3.5 sd (the rule) |
    | wall |
"""


def test_suggestion_benchmark_runs_and_reports_every_section(tmp_path: Path) -> None:
    printed, text = run_benchmark("suggestions", *TINY.split(), folder=tmp_path, timeout=600)
    assert printed == text  # printed and written alike
    assert_report_has(text, sections=SECTIONS, rows=ROWS)  # | 0.1 |: a stricter lead, held out
    lines = targets_of(text)
    assert len(lines) == 6
    assert re.match(r"- (PASS|FAIL): at least 95 % of offered spots within 1 %", lines[0])
    assert re.match(r"- (PASS|FAIL): none beyond 3 %", lines[1])
    assert re.search(r"of \d+ landmarks looked for in \d+ of the \d+ arenas\.$", lines[1])
    assert re.match(r"- (PASS|FAIL): at least 25 % of landmarks offered a spot", lines[2])
    assert re.match(r"- (PASS|FAIL): at least 90 % of shown suggestions", lines[3])
    assert "**" in text.split("## 5. Choosing the rule", 1)[1].split("## 6.", 1)[0]
