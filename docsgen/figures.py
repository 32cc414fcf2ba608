"""The benchmark figures of the README and docs/, from the reports the benchmarks write.

``python -m docsgen.figures`` (``make docs-figures``) rewrites every generated section of
``DOCS``, each between ``<!-- figures:NAME -->`` and ``<!-- end of figures:NAME -->``, from
the reports already in docs/; ``--check`` exits 1 when a doc is not what the reports say
(tests/test_docs_generated.py). Outside these sections the docs name no benchmark figure:
they point at the reports. ``--run`` (``make bench-all``) first runs every
benchmark at one commit, refusing a tree with uncommitted changes, so that each report
and the docs speak of the same code.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from docsgen.reports import Report, read_report, table_rows
from docsgen.sizing import sizing

ROOT = Path(__file__).parents[1]
README = ROOT / "README.md"
# Every doc with generated sections, relative to the root.
DOCS = ("README.md", "docs/benchmarks.md", "docs/geometry.md", "docs/deploy.md")
SECTION = re.compile(r"<!-- figures:([\w-]+) -->")


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
    Benchmark("bench-slow-phone", "docs/slow-phone.md", "one phone, its CPU throttled 4x"),
    Benchmark("bench-load", "docs/load-benchmark.md", "400 searches at once, nginx, PostgreSQL"),
    Benchmark("bench-reanchor", "docs/reanchor-benchmark.md", "live frames matched to the photo"),
)

# The solver table: the routes of docs/solver-benchmark.md's first table at 3 px.
SOLVER_SIGMA = "sigma 3 px"
SOLVER_ROUTES = ("projective", "phone prior", "EXIF focal")
SOLVER_LANDMARKS = (3, 4, 5, 8)
# What the report has no row for, and why; any other row missing is said to be missing.
SOLVER_NOT_RUN = {
    "projective 3+e1": "-",  # too few landmarks for the paper's method
    "projective 4+e1": "a curve",  # the paper's answer is no point
    "EXIF focal 8+e1": "-",  # the prior already leaves no room at 8
}


def link(report: str, doc: str) -> str:
    """A Markdown link to ``report`` from ``doc`` (both relative to the root)."""
    target = Path(report).name if Path(doc).parent == Path(report).parent else report
    return f"[{Path(report).name}]({target})"


def targets_table(root: Path, doc: str) -> str:
    """One row per benchmark: its command, report and commit, and each failed target."""
    rows = ["| command | what it plays | report (code of commit) | targets |", "|---|---|---|---|"]
    commits: set[str] = set()
    for bench in BENCHMARKS:
        report = read_report(root / bench.report)
        commits.add(report.commit)
        total = len(report.targets)
        verdicts = [f"{report.passed} of {total} met"] if total else ["none set"]
        verdicts += [f"**FAIL**: {claim}" for claim in report.failed]
        cell = f"{link(bench.report, doc)} ({report.commit})"
        rows.append(f"| `make {bench.target}` | {bench.plays} | {cell} | {'; '.join(verdicts)} |")
    return "\n".join(rows) + "\n\n" + one_code(sorted(commits))


# What the benchmarks measure: a report of another commit with the same tree here measured
# the same code (a later commit that changed only tests, docs or benchmarks).
APP_CODE = ("backend", "shared_solver", "frontend", "deploy", "requirements", "pyproject.toml")


def one_code(commits: list[str]) -> str:
    """Whether the reports of ``commits`` measured one version of the app's code."""
    if len(commits) == 1:
        return f"Every report is of commit {commits[0]}."
    listed = ", ".join(commits)
    try:
        changed = [
            git("diff", "--name-only", commits[0], other, "--", *APP_CODE) for other in commits[1:]
        ]
    except subprocess.CalledProcessError:  # a commit this clone does not have
        return f"The reports are of commits {listed}; this clone cannot compare them."
    folders = sorted({str(Path(name).parent) for diff in changed for name in diff.split()})
    if folders:
        places = ", ".join(f"`{folder}`" for folder in folders)
        return f"The reports are of commits {listed}, whose app code differs (in {places})."
    return (
        f"The reports are of commits {listed}, with the same app code "
        f"({', '.join(f'`{path}`' for path in APP_CODE)}): one version of the app measured."
    )


def report_targets(bench: Benchmark) -> Callable[[Path, str], str]:
    """A section for one benchmark: its report, commit and every target as the report
    words it, PASS or FAIL with the measure."""

    def section(root: Path, doc: str) -> str:
        where = f"{link(bench.report, doc)}, `make {bench.target}`"
        if not (root / bench.report).exists():
            return f"The report {where} is missing: run `make {bench.target}`."
        report: Report = read_report(root / bench.report)
        head = f"Targets in {where} (code of commit {report.commit})"
        if not report.targets:
            return f"{head}: none set; the report's tables say what each choice gives."
        lines = [f"{head}: {report.passed} of {len(report.targets)} met.", ""]
        return "\n".join(lines + [f"- {verdict}: {claim}" for verdict, claim in report.targets])

    return section


def solver_table(root: Path, doc: str) -> str:
    """Median / p90 error of where the friend is, px, by landmarks and route, at 3 px."""
    report = root / BENCHMARKS[0].report
    text = report.read_text(encoding="utf-8") if report.exists() else ""
    table = table_rows(text, SOLVER_SIGMA)
    if not table:
        return (
            f"{link(BENCHMARKS[0].report, doc)} has no table at {SOLVER_SIGMA}: run `make bench`."
        )
    column = table[0].index(SOLVER_SIGMA)
    cells = {row[0]: row[column] for row in table[1:] if len(row) > column}
    trials = re.search(r"Trials: (\d+) per cell", text)
    runs = f"{trials.group(1) if trials else '?'} trials, commit {read_report(report).commit}"
    rows = [
        f"| landmarks + friend marked ({runs}) | cameras unknown (the paper) | phone photos "
        "| lens known (EXIF) |",
        "|---|---|---|---|",
    ]
    for count in SOLVER_LANDMARKS:
        names = [f"{route} {count}+e1" for route in SOLVER_ROUTES]
        found = [cells.get(name, SOLVER_NOT_RUN.get(name, "not in the report")) for name in names]
        rows.append(f"| {count} | {' | '.join(found)} |")
    return "\n".join(rows)


def report_table(bench: Benchmark, header_cell: str) -> Callable[[Path, str], str]:
    """A section copying the report's table whose header has ``header_cell``, with its
    commit: for a report whose headline is a table rather than targets."""

    def section(root: Path, doc: str) -> str:
        path = root / bench.report
        rows = table_rows(path.read_text(encoding="utf-8"), header_cell) if path.exists() else []
        where = f"{link(bench.report, doc)}, `make {bench.target}`"
        if not rows:
            return f"{where} has no table with {header_cell!r}: run `make {bench.target}`."
        lines = [f"| {' | '.join(row)} |" for row in rows]
        lines.insert(1, "|" + "---|" * len(rows[0]))
        return "\n".join([f"From {where} (code of commit {read_report(path).commit}):", "", *lines])

    return section


SECTIONS: dict[str, Callable[[Path, str], str]] = {
    "solver": solver_table,
    "targets": targets_table,
    "sizing": lambda root, doc: sizing(root),
    "tap-regions": report_table(BENCHMARKS[4], "95 % region holds the truth"),
    **{f"targets-{bench.target}": report_targets(bench) for bench in BENCHMARKS},
}


def rendered(text: str, doc: str, root: Path = ROOT) -> str:
    """``text`` of ``doc`` with every generated section renewed from the reports under
    ``root``."""
    for name in SECTION.findall(text):
        if name not in SECTIONS:
            raise ValueError(f"{doc}: no generator for the section {name!r}")
        begin, end = f"<!-- figures:{name} -->", f"<!-- end of figures:{name} -->"
        head, _, rest = text.partition(begin)
        _, ended, tail = rest.partition(end)
        if not ended:
            raise ValueError(f"{doc} lacks {end!r} after {begin!r}")
        text = f"{head}{begin}\n{SECTIONS[name](root, doc)}\n{end}{tail}"
    return text


def git(*args: str) -> str:
    return subprocess.run(
        ["git", *args], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.strip()


def run_every_benchmark() -> int:
    """Every benchmark at HEAD, one after the other; a benchmark that stops leaves a report
    that says so, with one failed target, so the docs show it as failed. Returns how
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
    mode.add_argument("--check", action="store_true", help="exit 1 if a doc is stale")
    mode.add_argument("--run", action="store_true", help="run every benchmark first")
    args = parser.parse_args(argv)
    stopped = run_every_benchmark() if args.run else 0
    if stopped < 0:
        return 2
    stale = []
    for doc in DOCS:
        text = (ROOT / doc).read_text(encoding="utf-8")
        fresh = rendered(text, doc)
        if fresh != text:
            stale.append(doc)
            if not args.check:
                (ROOT / doc).write_text(fresh, encoding="utf-8")
    if args.check:
        print("\n".join(f"{doc} is stale: make docs-figures" for doc in stale), file=sys.stderr)
        return int(bool(stale))
    return int(stopped > 0)


if __name__ == "__main__":
    sys.exit(main())
