"""A benchmark run as its make target runs it: a script of ``benchmarks/`` in a subprocess
from the repository root (Locust patches the standard library of its process)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def run_benchmark(name: str, *options: str, folder: Path, timeout: float) -> tuple[str, str]:
    """``benchmarks/<name>.py`` with ``options``: what it printed and its report (in ``folder``).
    Fails unless it exits cleanly within ``timeout`` s (beyond it hangs)."""
    script = ROOT / "benchmarks" / f"{name}.py"
    out = folder / f"{name}.md"
    done = subprocess.run(
        [sys.executable, str(script), *options, "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-4000:]
    return done.stdout, out.read_text()


def lines_of(block: str) -> list[str]:
    """The non-blank lines of a text block, stripped: a list written as the reader sees it."""
    return [line.strip() for line in block.splitlines() if line.strip()]


def assert_report_has(text: str, *, sections: str, rows: str = "") -> None:
    """``text`` has each line of ``sections`` (headings, in this order) and of ``rows``."""
    positions = [text.index(title) for title in lines_of(sections)]
    assert positions == sorted(positions), positions
    for row in lines_of(rows):
        assert row in text, row


def targets_of(text: str, end: str | None = None) -> list[str]:
    """The ``- `` lines of the report's Targets section, up to ``end`` when given."""
    targets = text.split("## Targets", 1)[1]
    if end is not None:
        targets = targets.split(end, 1)[0]
    return [line for line in targets.splitlines() if line.startswith("- ")]
