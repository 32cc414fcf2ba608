"""docs/deploy.md's sizing: a stadium's demand from what one search spent in the load run.

The figures per search are read from the ``Per search`` table of docs/load-benchmark.md
(``make bench-load``); the stadium's figures are that times the rate of searches below.
A row the report lacks is named in the doc, and what depends on it left out.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from docsgen.reports import read_report, section_table

LOAD_REPORT = "docs/load-benchmark.md"

# The stadium: 5 % of a 50,000-seat crowd searching within the same half hour.
SEATS, SEARCHING, WINDOW_S = 50_000, 0.05, 1800
# What the app sends that the load run's 1600 px photos do not: 2560 px photos (about 1 MB
# each, docs/app.md) and a suggested spot per landmark found. Half again for the replicas.
APP_PHOTOS_MB, APP_EXTRA = 2.0, 1.5
# A replica is one Python process; kept at a third of a core, a burst still finds room.
REPLICA_SHARE = 1 / 3

ROWS = {
    "cpu": "CPU per completed search (ms)",
    "duration": "search duration p50 / max (s)",
    "memory": "peak memory (PSS, MB)",
    "bytes": "bytes per search: from the phones / to the phones",
    "wal": "PostgreSQL: peak database size / WAL written per search",
}


def numbers(cell: str) -> list[float]:
    return [float(found) for found in re.findall(r"\d+(?:\.\d+)?", cell)]


def per_search(root: Path) -> tuple[dict[str, list[float]], list[str]]:
    """Each row of ``ROWS`` as its numbers, and the rows the report lacks."""
    path = root / LOAD_REPORT
    table = section_table(path.read_text(encoding="utf-8"), "Per search") if path.exists() else {}
    found: dict[str, list[float]] = {}
    for key, label in ROWS.items():
        row = next((value for cell, value in table.items() if cell.startswith(label)), None)
        if row is not None and numbers(row):
            found[key] = numbers(row)
    return found, [label for key, label in ROWS.items() if key not in found]


def sizing(root: Path) -> str:
    """The per-search table and the stadium's demand, as Markdown."""
    found, missing = per_search(root)
    commit = read_report(root / LOAD_REPORT).commit
    lines = [
        f"Per search in [load-benchmark.md](load-benchmark.md) (code of commit {commit}; "
        "1600 px photos, no suggested spot):",
        "",
        "| per search | measured |",
        "|---|---|",
    ]
    if "cpu" in found:
        nginx, replicas, postgres = found["cpu"][:3]
        lines.append(
            f"| CPU: nginx (TLS included) / replicas / PostgreSQL | {nginx:g} / "
            f"{replicas:g} / {postgres:g} ms |"
        )
    if "bytes" in found:
        up, down = found["bytes"][:2]
        lines.append(
            f"| bytes: from the phones / to the phones (bodies) | {up:g} MB / {down:g} MB |"
        )
    if "wal" in found:
        lines.append(f"| PostgreSQL write-ahead log | {found['wal'][1]:g} MB |")
    if "duration" in found:
        lines.append(
            f"| how long a search lasts (people's pauses and queueing, p50) | "
            f"{found['duration'][0]:g} s |"
        )
    if "memory" in found:
        lines.append(f"| replica memory (PSS, peak, both replicas) | {found['memory'][1]:g} MB |")
    lines += [f"| {label} | not in the report |" for label in missing]
    return "\n".join([*lines, "", *stadium(found)])


def stadium(found: dict[str, list[float]]) -> list[str]:
    """The stadium's demand, row by row, from the figures per search."""
    searches = SEATS * SEARCHING
    rate = searches / WINDOW_S
    lines = [
        f"**A {SEATS:,}-seat stadium, {SEARCHING * 100:g} % of the crowd searching within the same "
        f"half hour**: {searches:,.0f} searches in {WINDOW_S:,} s, **{rate:.2f} searches per "
        "second**.",
    ]
    if "duration" in found:
        at_once = rate * found["duration"][0]
        lines[0] = lines[0][:-1] + (
            f", about {at_once:.0f} at once ({rate:.2f} x {found['duration'][0]:g} s), "
            f"{2 * at_once:.0f} phones with their event streams open."
        )
    lines += ["", "| | demand | what to run |", "|---|---|---|"]
    if "cpu" in found:
        nginx, replicas, postgres = (rate * ms / 1000 for ms in found["cpu"][:3])
        needed = math.ceil(replicas * APP_EXTRA / REPLICA_SHARE)
        memory = (
            f"; {found['memory'][1] / 2 / 1000:.1f} GB of memory each" if "memory" in found else ""
        )
        lines += [
            f"| replicas | {rate:.2f} x {found['cpu'][1]:g} ms = **{replicas:.2f} cores** "
            f"({replicas * APP_EXTRA:.2f} with half again for 2560 px photos and the suggested "
            f"spots) | at a third of a core each, **{needed} replicas**, and one more so that "
            f"losing one leaves the others at it: **{needed + 1}**{memory}. |",
            f"| PostgreSQL | {rate:.2f} x {found['cpu'][2]:g} ms = **{postgres:.2f} cores** | "
            "**2 vCPU and 4 GB** of memory (the photos' bytes and the erase, not the CPU, size "
            "it); the disk for the photos and the WAL below. |",
            f"| nginx | {rate:.2f} x {found['cpu'][0]:g} ms = {nginx:.2f} cores | one small "
            "instance (or the cloud's load balancer); two connections per open stream. |",
        ]
    if "bytes" in found:
        inbound, outbound = rate * APP_PHOTOS_MB, rate * found["bytes"][1]
        lines.append(
            f"| bandwidth | in: the app's two photos, {rate:.2f} x {APP_PHOTOS_MB:g} MB = "
            f"{inbound:.1f} MB/s; out: {rate:.2f} x {found['bytes'][1]:g} MB = {outbound:.2f} "
            f"MB/s | **about {inbound * 8:.0f} Mbit/s in and {max(outbound * 8, 1):.0f} Mbit/s "
            "out** on average; twice that for a rush within the half hour. |"
        )
    if "duration" in found:
        least = rate * found["duration"][0] * APP_PHOTOS_MB / 1000
        lines.append(
            "| database size | photos stay until **Delete now** or the 2-hour expiry | from "
            f"the photos of the searches at once ({least:.2f} GB) when people delete, to all "
            f"{searches:,.0f} (**{searches * APP_PHOTOS_MB / 1000:.0f} GB**) when nobody does, "
            "plus deleted rows until the next erase. |"
        )
    if "wal" in found:
        wal = rate * found["wal"][1]
        lines.append(
            f"| write-ahead log | {rate:.2f} x {found['wal'][1]:g} MB = {wal:.1f} MB/s (at "
            f"1600 px) | {wal * WINDOW_S / 1000:.1f} GB per half hour: size `max_wal_size` and "
            "the disk for it; any WAL archive or backup holds the photos' bytes too. |"
        )
    # Without a figure per search there is no demand to show: the headline alone.
    return lines if len(lines) > 4 else lines[:1]
