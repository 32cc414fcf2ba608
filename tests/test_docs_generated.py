"""The docs generated from the code are what the code says now (docsgen/)."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from backend.errors import MEANING, STATUS, ErrorCode
from docsgen import error_codes, figures
from shared_solver import errors as solver_errors


def test_every_code_has_a_meaning() -> None:
    assert set(MEANING) == set(ErrorCode) == set(STATUS)
    assert set(solver_errors.MEANING) == set(solver_errors.ErrorCode)
    assert set(solver_errors.WARNING_MEANING) == set(solver_errors.WarningCode)


def test_the_api_doc_lists_every_code_as_the_code_says() -> None:
    assert error_codes.main(["--check"]) == 0, "renew it: python -m docsgen.error_codes"
    listed = error_codes.API_DOC.read_text(encoding="utf-8")
    every = [
        *ErrorCode,
        *solver_errors.ErrorCode,
        *solver_errors.Reason,
        *solver_errors.WarningCode,
    ]
    for code in every:
        assert f"| `{code}` |" in listed


def test_a_changed_meaning_makes_the_doc_stale(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(MEANING, ErrorCode.BUSY, "a meaning nobody wrote down")
    assert error_codes.main(["--check"]) == 1


def test_a_changed_warning_meaning_makes_the_doc_stale(monkeypatch: pytest.MonkeyPatch) -> None:
    code = solver_errors.WarningCode.BEHIND_YOU
    monkeypatch.setitem(solver_errors.WARNING_MEANING, code, "a meaning nobody wrote down")
    assert error_codes.main(["--check"]) == 1


def test_the_readme_tables_are_what_the_reports_say() -> None:
    assert figures.main(["--check"]) == 0, "renew them: make docs-figures"


@pytest.fixture
def reports(tmp_path: Path) -> Path:
    """A copy of the reports the README's tables are made from."""
    for bench in figures.BENCHMARKS:
        copy = tmp_path / bench.report
        copy.parent.mkdir(parents=True, exist_ok=True)
        copy.write_text((figures.ROOT / bench.report).read_text(encoding="utf-8"))
    return tmp_path


def test_a_failed_target_shows_in_the_readme_as_failed(reports: Path) -> None:
    readme = figures.README.read_text(encoding="utf-8")
    solver = reports / figures.BENCHMARKS[0].report
    text = solver.read_text(encoding="utf-8")
    passed = re.search(r"^- PASS: (.*)$", text, re.M)
    assert passed is not None
    solver.write_text(text.replace(passed.group(0), f"- FAIL: {passed.group(1)}"))
    stale = figures.rendered(readme, reports)
    assert stale != readme
    assert f"**FAIL**: {figures.shortened(passed.group(1))}" in stale


def test_the_solver_table_reads_the_reports_figures(reports: Path) -> None:
    solver = reports / figures.BENCHMARKS[0].report
    text = solver.read_text(encoding="utf-8")
    row = re.search(r"^\| phone prior 5\+e1 \| [^|]+ \| ([^|]+) \|", text, re.M)  # 3 px
    assert row is not None
    solver.write_text(
        text.replace(row.group(0), row.group(0).replace(row.group(1), " 1.23 / 4.56 "))
    )
    assert "| 5 | 17.8 / 134 | 1.23 / 4.56 |" in figures.solver_table(reports)


def test_a_benchmark_that_stops_shows_as_failed(reports: Path) -> None:
    bench = figures.BENCHMARKS[-1]
    (reports / bench.report).write_text(figures.stopped_report(bench, "abc1234", 2))
    report = figures.read_report(reports / bench.report)
    assert (report.commit, report.passed) == ("abc1234", 0)
    assert report.failed == ("the benchmark runs to its end (exit status 2)",)


def test_running_every_benchmark_refuses_uncommitted_changes(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    ran: list[object] = []
    monkeypatch.setattr(figures, "git", lambda *args: " M backend/main.py")
    monkeypatch.setattr(subprocess, "run", lambda *args, **kwargs: ran.append(args))
    assert figures.main(["--run"]) == 2
    assert ran == []
