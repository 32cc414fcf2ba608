"""Reading the reports the benchmarks write in docs/: commit, targets, a table's rows.

Every reader answers ``None`` (or an empty collection) for what a report lacks, so that a
generated section can say what is missing instead of stopping the whole renewal.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

TARGET = re.compile(r"^- (PASS|FAIL): (.*)$", re.M)
COMMIT = re.compile(r"\bcommit ([0-9a-f]{7,40})\b")


@dataclass(frozen=True)
class Report:
    """What the docs say of one report: its commit and its targets, each as written."""

    commit: str
    targets: tuple[tuple[str, str], ...]  # (PASS or FAIL, the target and its measure)

    @property
    def passed(self) -> int:
        return sum(verdict == "PASS" for verdict, _ in self.targets)

    @property
    def failed(self) -> tuple[str, ...]:
        """Each failed target, shortened to its claim and measure."""
        return tuple(shortened(claim) for verdict, claim in self.targets if verdict == "FAIL")


def shortened(target: str) -> str:
    """A target's text up to its first ``;`` (the rest explains), brackets closed."""
    head = target.split("; ", 1)[0].rstrip(".")
    return head + ")" * (head.count("(") - head.count(")"))


def read_report(path: Path) -> Report:
    """The report at ``path``; commit ``unknown`` and no targets when it is missing."""
    text = path.read_text(encoding="utf-8") if path.exists() else ""
    commit = COMMIT.search(text)
    return Report(
        commit=commit.group(1) if commit else "unknown",
        targets=tuple((verdict, claim) for verdict, claim in TARGET.findall(text)),
    )


def table_rows(text: str, header_cell: str) -> list[list[str]]:
    """The rows (cells stripped, header included) of the first Markdown table whose header
    row has a cell ``header_cell``; empty when there is none."""
    lines = text.splitlines()
    for at, line in enumerate(lines):
        if line.startswith("|") and header_cell in cells(line):
            rows = [cells(line)]
            for row in lines[at + 2 :]:
                if not row.startswith("|"):
                    break
                rows.append(cells(row))
            return rows
    return []


def cells(line: str) -> list[str]:
    return [cell.strip() for cell in line.strip().strip("|").split("|")]


def section_table(text: str, heading: str) -> dict[str, str]:
    """First cell -> second cell of the first table under the ``## heading`` of a report,
    bold marks dropped; empty when the heading or its table is missing."""
    _, found, rest = text.partition(f"\n## {heading}\n")
    if not found:
        return {}
    rest = rest.split("\n## ", 1)[0]
    table: dict[str, str] = {}
    for line in rest.splitlines():
        row = cells(line.replace("**", "")) if line.startswith("|") else []
        if len(row) >= 2 and not set(row[1]) <= set("-"):
            table[row[0]] = row[1]
    return table
