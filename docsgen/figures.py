"""The README's benchmark figures, from the reports the benchmarks write in docs/.

``python -m docsgen.figures`` (``make docs-figures``) rewrites the README's generated
sections, each between ``<!-- figures:NAME -->`` and ``<!-- end of figures:NAME -->``, from
the reports already in docs/; ``--check`` exits 1 when the README is not what the reports
say (tests/test_docs_generated.py). ``--run`` (``make bench-all``) first runs every
benchmark at one commit, refusing a tree with uncommitted changes, so that each report
and the README speak of the same code.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).parents[1]
README = ROOT / "README.md"


@dataclass(frozen=True)
class Benchmark:
    """One ``make`` target, the report it writes (relative to the root) and what it plays."""

    target: str
    report: str
    plays: str


BENCHMARKS = (
    Benchmark("bench", "docs/solver-benchmark.md", "every method on the same random phone scenes"),
    Benchmark("bench-camera", "docs/camera-checks.md", "each choice of the camera model"),
    Benchmark("bench-real", "docs/real-cameras.md", "the solver on real calibrated photographs"),
    Benchmark("bench-api", "docs/api-benchmark.md", "`/api/solve`, 12 MP uploads, overlays"),
    Benchmark("bench-taps", "docs/tap-precision.md", "200 searches, finger taps on two phones"),
    Benchmark("bench-suggest", "docs/suggestions.md", "rendered arenas full of look-alikes"),
    Benchmark("bench-network", "docs/network-benchmark.md", "a search on a congested venue"),
    Benchmark("bench-load", "docs/load-benchmark.md", "400 searches at once, nginx, PostgreSQL"),
)

# The solver table: the routes of docs/solver-benchmark.md's first table at 3 px.
SOLVER_SIGMA = "sigma 3 px"
SOLVER_ROUTES = ("projective", "phone prior", "EXIF focal")
SOLVER_LANDMARKS = (3, 4, 5, 8)
# What the report has no row for because the answer is no point: the paper's curve.
SOLVER_NO_POINT = {"projective 4+e1": "a curve"}

TARGET = re.compile(r"^- (PASS|FAIL): (.*)$", re.M)
COMMIT = re.compile(r"\bcommit ([0-9a-f]{7,40})\b")


@dataclass(frozen=True)
class Report:
    """What the README says of one report: its commit and its targets' verdicts."""

    commit: str
    passed: int
    failed: tuple[str, ...]  # each failed target, shortened to its claim and measure


def shortened(target: str) -> str:
    """A target's text up to its first ``;`` (the rest explains), brackets closed."""
    head = target.split("; ", 1)[0].rstrip(".")
    return head + ")" * (head.count("(") - head.count(")"))


def read_report(path: Path) -> Report:
    text = path.read_text(encoding="utf-8")
    commit = COMMIT.search(text)
    verdicts = TARGET.findall(text)
    return Report(
        commit=commit.group(1) if commit else "unknown",
        passed=sum(verdict == "PASS" for verdict, _ in verdicts),
        failed=tuple(shortened(claim) for verdict, claim in verdicts if verdict == "FAIL"),
    )


def targets_table(root: Path) -> str:
    """One row per benchmark: its command, report and commit, and each failed target."""
    rows = ["| command | what it plays | report (code of commit) | targets |", "|---|---|---|---|"]
    for bench in BENCHMARKS:
        report = read_report(root / bench.report)
        total = report.passed + len(report.failed)
        verdicts = [f"{report.passed} of {total} met"] if total else ["none set"]
        verdicts += [f"**FAIL**: {claim}" for claim in report.failed]
        link = f"[{Path(bench.report).name}]({bench.report}) ({report.commit})"
        rows.append(f"| `make {bench.target}` | {bench.plays} | {link} | {'; '.join(verdicts)} |")
    return "\n".join(rows)


def solver_table(root: Path) -> str:
    """Median / p90 error of where the friend is, px, by landmarks and route, at 3 px."""
    report = root / BENCHMARKS[0].report
    text = report.read_text(encoding="utf-8")
    header = next(line for line in text.splitlines() if SOLVER_SIGMA in line)
    column = [cell.strip() for cell in header.strip("|").split("|")].index(SOLVER_SIGMA)
    cells: dict[str, str] = {}
    for line in text[text.index(header) :].splitlines()[2:]:
        if not line.startswith("|"):
            break
        row = [cell.strip() for cell in line.strip("|").split("|")]
        cells[row[0]] = row[column]
    commit = read_report(report).commit
    trials = re.search(r"Trials: (\d+) per cell", text)
    runs = f"{trials.group(1) if trials else '?'} trials, commit {commit}"
    rows = [
        f"| landmarks + friend marked ({runs}) | cameras unknown (the paper) | phone photos "
        "| lens known (EXIF) |",
        "|---|---|---|---|",
    ]
    for count in SOLVER_LANDMARKS:
        names = [f"{route} {count}+e1" for route in SOLVER_ROUTES]
        found = [cells.get(name, SOLVER_NO_POINT.get(name, "-")) for name in names]
        rows.append(f"| {count} | {' | '.join(found)} |")
    return "\n".join(rows)


SECTIONS = {"solver": solver_table, "targets": targets_table}


def rendered(readme: str, root: Path = ROOT) -> str:
    """``readme`` with every generated section renewed from the reports under ``root``."""
    for name, make in SECTIONS.items():
        begin, end = f"<!-- figures:{name} -->", f"<!-- end of figures:{name} -->"
        head, found, rest = readme.partition(begin)
        _, ended, tail = rest.partition(end)
        if not (found and ended):
            raise ValueError(f"{README.name} lacks the markers {begin!r} ... {end!r}")
        readme = f"{head}{begin}\n{make(root)}\n{end}{tail}"
    return readme


def git(*args: str) -> str:
    return subprocess.run(
        ["git", *args], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.strip()


def run_every_benchmark() -> int:
    """Every benchmark at HEAD, one after the other; a benchmark that stops leaves a report
    that says so, with one failed target, so the README shows it as failed. Returns how
    many stopped."""
    if git("status", "--porcelain"):
        print(
            "uncommitted changes: commit them first, the reports name one commit", file=sys.stderr
        )
        return -1
    commit = git("rev-parse", "--short", "HEAD")
    stopped = 0
    for bench in BENCHMARKS:
        print(f"[make {bench.target}] at commit {commit} ...", file=sys.stderr, flush=True)
        make = ["make", "--no-print-directory", bench.target]
        status = subprocess.run(make, check=False, cwd=ROOT).returncode
        if status != 0:
            stopped += 1
            (ROOT / bench.report).write_text(stopped_report(bench, commit, status), "utf-8")
    return stopped


def stopped_report(bench: Benchmark, commit: str, status: int) -> str:
    """The report of a benchmark that did not run to its end: one failed target."""
    return (
        f"# make {bench.target}\n\n- commit {commit}: the run stopped (exit status {status}); "
        "the last report that ran to its end is in git\n\n## Targets\n\n"
        f"- FAIL: the benchmark runs to its end (exit status {status})\n"
    )


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true", help="exit 1 if the README is stale")
    mode.add_argument("--run", action="store_true", help="run every benchmark first")
    args = parser.parse_args(argv)
    stopped = run_every_benchmark() if args.run else 0
    if stopped < 0:
        return 2
    readme = README.read_text(encoding="utf-8")
    fresh = rendered(readme)
    if args.check:
        return int(fresh != readme)
    README.write_text(fresh, encoding="utf-8")
    return int(stopped > 0)


if __name__ == "__main__":
    sys.exit(main())
