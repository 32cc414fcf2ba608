"""The docs generated from the code are what the code says now (docsgen/)."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from backend.errors import MEANING, STATUS, ErrorCode
from docsgen import error_codes, figures, sizing
from docsgen.reports import read_report, shortened
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


def test_every_doc_is_what_the_reports_say() -> None:
    assert figures.main(["--check"]) == 0, "renew them: make docs-figures"


# A commit's short hash or longer: hex with a digit and a letter (no English word is).
RUN_COMMIT = re.compile(r"\b(?=[0-9a-f]*\d)(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}\b")


def test_no_doc_names_a_runs_commit_outside_its_generated_sections() -> None:
    """A run's commit in prose means a figure copied by hand from a report."""
    reports = {bench.report for bench in figures.BENCHMARKS}
    docs = ["README.md", *(f"docs/{path.name}" for path in (figures.ROOT / "docs").glob("*.md"))]
    assert set(figures.DOCS) <= set(docs)
    for doc in sorted(set(docs) - reports):
        text = (figures.ROOT / doc).read_text(encoding="utf-8")
        prose = re.sub(
            r"<!-- figures:([\w-]+) -->.*?<!-- end of figures:\1 -->", "", text, flags=re.S
        )
        named = RUN_COMMIT.findall(prose)
        assert not named, (
            f"{doc} names {named}: generate the figure (docsgen/figures.py) or cite the report"
        )


@pytest.fixture
def reports(tmp_path: Path) -> Path:
    """A copy of the reports the docs' figures are made from."""
    for bench in figures.BENCHMARKS:
        copy = tmp_path / bench.report
        copy.parent.mkdir(parents=True, exist_ok=True)
        copy.write_text((figures.ROOT / bench.report).read_text(encoding="utf-8"))
    return tmp_path


def test_a_failed_target_shows_in_the_docs_as_failed(reports: Path) -> None:
    solver = reports / figures.BENCHMARKS[0].report
    text = solver.read_text(encoding="utf-8")
    passed = re.search(r"^- PASS: (.*)$", text, re.M)
    assert passed is not None
    solver.write_text(text.replace(passed.group(0), f"- FAIL: {passed.group(1)}"))
    stale = {}
    for doc in ("README.md", "docs/benchmarks.md"):
        fresh = (figures.ROOT / doc).read_text(encoding="utf-8")
        stale[doc] = figures.rendered(fresh, doc, reports)
        assert stale[doc] != fresh
    assert f"**FAIL**: {shortened(passed.group(1))}" in stale["README.md"]
    assert f"- FAIL: {passed.group(1)}" in stale["docs/benchmarks.md"]


def test_the_solver_table_reads_the_reports_figures(reports: Path) -> None:
    solver = reports / figures.BENCHMARKS[0].report
    text = solver.read_text(encoding="utf-8")
    row = re.search(r"^\| phone prior 5\+e1 \| [^|]+ \| ([^|]+) \|", text, re.M)  # 3 px
    assert row is not None
    solver.write_text(
        text.replace(row.group(0), row.group(0).replace(row.group(1), " 1.23 / 4.56 "))
    )
    assert "| 5 | 17.8 / 134 | 1.23 / 4.56 |" in figures.solver_table(reports, "README.md")


def test_the_stadium_is_sized_from_the_load_reports_figures(reports: Path) -> None:
    load = reports / sizing.LOAD_REPORT
    text = load.read_text(encoding="utf-8")
    row = re.search(r"^\| \*\*CPU per completed search.*$", text, re.M)
    assert row is not None
    load.write_text(
        text.replace(
            row.group(0),
            f"| {sizing.ROWS['cpu']}: nginx / replicas / PostgreSQL / load generator "
            "| 18 / 900 / 36 / 100 |",
        )
    )
    sized = sizing.sizing(reports)
    assert "| CPU: nginx (TLS included) / replicas / PostgreSQL | 18 / 900 / 36 ms |" in sized
    # 2,500 searches in 1,800 s: 1.39 a second, each 0.9 s of a replica, half again.
    assert "1.39 x 900 ms = **1.25 cores** (1.88 with half again" in sized
    assert "**6 replicas**" in sized


def test_a_missing_row_or_report_is_said_not_crashed_on(reports: Path) -> None:
    load = reports / sizing.LOAD_REPORT
    text = load.read_text(encoding="utf-8")
    load.write_text(re.sub(r"^\| PostgreSQL: peak database size.*\n", "", text, flags=re.M))
    sized = sizing.sizing(reports)
    assert f"| {sizing.ROWS['wal']} | not in the report |" in sized
    assert "write-ahead log |" not in sized
    solver = reports / figures.BENCHMARKS[0].report
    text = solver.read_text(encoding="utf-8")
    solver.write_text(re.sub(r"^\| phone prior 5\+e1 \|.*\n", "", text, flags=re.M))
    assert "| 5 | 17.8 / 134 | not in the report |" in figures.solver_table(reports, "README.md")
    solver.unlink()
    bench = figures.SECTIONS["targets-bench"](reports, "docs/benchmarks.md")
    assert bench.endswith("is missing: run `make bench`.")
    assert "has no table" in figures.solver_table(reports, "README.md")


def test_a_benchmark_that_stops_shows_as_failed(reports: Path) -> None:
    bench = next(b for b in figures.BENCHMARKS if b.target == "bench-load")
    (reports / bench.report).write_text(figures.stopped_report(bench, "abc1234", 2))
    report = read_report(reports / bench.report)
    assert (report.commit, report.passed) == ("abc1234", 0)
    assert report.failed == ("the benchmark runs to its end (exit status 2)",)
    sized = sizing.sizing(reports)  # the load report: no figure per search, no demand
    assert f"| {sizing.ROWS['cpu']} | not in the report |" in sized
    assert "| demand |" not in sized


def test_running_every_benchmark_refuses_uncommitted_changes(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    ran: list[object] = []
    monkeypatch.setattr(figures, "git", lambda *args: " M backend/main.py")
    monkeypatch.setattr(subprocess, "run", lambda *args, **kwargs: ran.append(args))
    assert figures.main(["--run"]) == 2
    assert ran == []


def test_reports_of_several_commits_say_whether_they_measured_one_app() -> None:
    head = figures.git("rev-parse", "--short", "HEAD")
    first = figures.git("rev-list", "--max-parents=0", "HEAD").split()[0][:7]
    assert figures.one_code([head]) == f"Every report is of commit {head}."
    assert "the same app code" in figures.one_code([head, head])
    differs = figures.one_code([first, head])
    assert "whose app code differs (in `" in differs
    assert "`shared_solver/matching`" in differs  # where, by folder
    assert "cannot compare" in figures.one_code([head, "0000000"])
