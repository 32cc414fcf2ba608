"""The suggestion benchmark's tables, from the scenes' measurements (:mod:`.trials`)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TypeVar

import numpy as np
from report import markdown_table, ms, percentile

from shared_solver.estimation.uncertainty import chi2_quantile
from shared_solver.matching import FLAG_SIGMAS, LEVEL
from shared_solver.matching.suggestion import RULES, Evidence, Rules, decide

from .arenas import Asked
from .trials import Absent, SceneRun, Searched, Timed

TARGET_PRECISION = 0.90
SIFT_SUPPORT = (1, 2, 3)
FLAGS = (3.0, FLAG_SIGMAS, 4.0)
# An offered spot farther than this from the truth (fraction of the diagonal) is far off:
# the arenas' target is none (``arena_tables``).
FAR = 0.03

Rule = Callable[[Evidence], bool]
Item = TypeVar("Item", bound=Asked | Searched)


@dataclass(frozen=True)
class Offered:
    """Spots offered (suggestions shown) under one rule: of how many landmarks asked for,
    how many offered, right (within 1 % of the diagonal), far (beyond :data:`FAR`), and the
    worst error (fraction)."""

    asked: int
    offered: int
    right: int
    far: int = 0
    worst: float = 0.0

    @property
    def coverage(self) -> float:
        return self.offered / self.asked if self.asked else math.nan

    @property
    def precision(self) -> float:
        return self.right / self.offered if self.offered else math.nan

    def cells(self) -> list[str]:
        """The halls' cells: offered of asked, right of offered."""
        return [
            f"{self.offered} of {self.asked} ({share(self.coverage)})",
            f"{self.right} of {self.offered} ({share(self.precision)})",
        ]

    def arena_cells(self) -> list[str]:
        """The arenas' cells (``arena_tables.HEADER``)."""
        worst = "-" if self.offered == 0 else f"{100 * self.worst:.1f} %"
        return [
            str(self.asked),
            f"{self.offered} ({share(self.coverage)})",
            f"{self.right} ({share(self.precision)})",
            str(self.far),
            worst,
        ]


def share(value: float) -> str:
    """A fraction as a percentage to 0.1 %; "-" for NaN (nothing to count)."""
    return "-" if math.isnan(value) else f"{100 * value:.1f} %"


def by_rule(rules: Rules = RULES) -> Rule:
    """A rule of the code's kind, with these thresholds."""
    return lambda evidence: decide(evidence, rules) is not None


IN_CODE = by_rule()


def suggested(timed: Timed | None, rules: Rules) -> bool:
    """Whether the search's evidence gives a suggestion under ``rules``."""
    return (
        timed is not None
        and timed.evidence is not None
        and decide(timed.evidence, rules) is not None
    )


def shown(
    items: Sequence[Item], pick: Callable[[Item], Timed | None], rule: Rule = IN_CODE
) -> Offered:
    """The spots ``rule`` offers from each item's search (``pick``), judged."""
    errors = [error for _, error in offers(items, pick, rule)]
    return Offered(
        len(items),
        len(errors),
        sum(error <= 0.01 for error in errors),
        sum(error > FAR for error in errors),
        max(errors, default=0.0),
    )


def offers(
    items: Sequence[Item], pick: Callable[[Item], Timed | None], rule: Rule = IN_CODE
) -> list[tuple[Item, float]]:
    """Each item whose search (``pick``) ``rule`` offers a spot for, with that spot's
    distance from the truth (fraction of the diagonal)."""
    found = []
    for item in items:
        timed = pick(item)
        if timed is not None and timed.evidence is not None and rule(timed.evidence):
            found.append((item, item.error(timed)))
    return found


def scenes_table(runs: Sequence[SceneRun]) -> str:
    rows = []
    for stream in ("calibration", "evaluation"):
        mine = [run for run in runs if run.stream == stream]
        if not mine:
            continue
        answered = [run for run in mine if run.answered]
        kinds = sorted({item.kind for run in answered for item in run.searched})
        per_kind = ", ".join(
            f"{kind} {sum(item.kind == kind for run in answered for item in run.searched)}"
            for kind in kinds
        )
        rows.append(
            [
                stream,
                str(len(mine)),
                str(len(answered)),
                f"{np.median([run.landmarks for run in mine]):.0f}",
                str(sum(len(run.searched) for run in answered)),
                per_kind,
                str(sum(len(run.absent) for run in answered)),
                f"{np.median([run.render_seconds for run in mine]):.2f} s",
            ]
        )
    header = [
        "scenes",
        "rendered",
        "answered",
        "landmarks both photos show (median)",
        "landmarks searched (both directions)",
        "by kind",
        "spots one photo only shows, searched",
        "render time per pair (median)",
    ]
    return markdown_table(header, rows)


def band_table(runs: Sequence[SceneRun]) -> str:
    answered = [run for run in runs if run.answered]
    rows = []
    for used in sorted({used for run in answered for used in run.band_offsets}):
        offsets = [
            o for run in answered for o in run.band_offsets.get(used, []) if not math.isnan(o)
        ]
        z = math.sqrt(chi2_quantile(LEVEL, 1))
        inside = sum(o <= z for o in offsets)
        rows.append(
            [
                f"{used} landmarks + friend 2",
                str(len(offsets)),
                f"{inside} ({share(inside / len(offsets) if offsets else math.nan)})",
                share(
                    sum(o <= FLAG_SIGMAS for o in offsets) / len(offsets) if offsets else math.nan
                ),
            ]
        )
    return markdown_table(
        [
            "answer from",
            "landmarks checked (photo 1 -> 2)",
            f"truth inside its {100 * LEVEL:.0f} % band",
            f"within {FLAG_SIGMAS:g} sd",
        ],
        rows,
    )


def band_sizes(searched: Sequence[Searched]) -> str:
    widths = [s.half_width for s in searched if not math.isnan(s.half_width)]
    lengths = [s.length for s in searched if s.length > 0]
    if not widths:
        return "(no band measured)"
    return (
        f"Band half-width at the true landmark: median {np.median(widths):.1f} px, "
        f"90th percentile {percentile(widths, 90):.1f} px, largest {max(widths):.0f} px; "
        f"band length median {np.median(lengths):.0f} px (photos 2560 px on the long side)."
    )


def headline(searched: Sequence[Searched], absent: Sequence[Absent]) -> tuple[str, Offered]:
    result = shown(searched, lambda s: s.colour)
    rows = [["every landmark", *result.cells(), _median_error(searched)]]
    for direction in (1, 2):
        part = [s for s in searched if s.direction == direction]
        rows.append(
            [
                f"tapped in photo {direction}",
                *shown(part, lambda s: s.colour).cells(),
                _median_error(part),
            ]
        )
    table = markdown_table(
        [
            "landmarks",
            "get a suggestion",
            "within 1 % of the diagonal",
            "error of the right ones (median)",
        ],
        rows,
    )
    searched_absent = [a for a in absent if a.band]
    wrong = sum(suggested(a.colour, RULES) for a in searched_absent)
    spots = (
        f"Spots one photo shows and the other does not: {len(absent)} tapped, "
        f"{len(searched_absent)} with a band crossing the other photo, **{wrong} suggested** "
        "(every one would be wrong)."
    )
    return table + "\n\n" + spots, result


def _median_error(searched: Sequence[Searched]) -> str:
    """Median distance of the right suggestions from the truth, px."""
    errors = [
        s.error(s.colour) * s.diagonal
        for s in searched
        if suggested(s.colour, RULES) and s.error(s.colour) <= 0.01
    ]
    return f"{np.median(errors):.1f} px" if errors else "-"


def kinds_table(searched: Sequence[Searched]) -> str:
    rows = []
    for kind in sorted({s.kind for s in searched}):
        mine = [s for s in searched if s.kind == kind]
        found = [s for s in mine if s.error(s.colour) <= 0.01]
        rows.append(
            [
                kind,
                *shown(mine, lambda s: s.colour).cells(),
                f"{len(found)} ({share(len(found) / len(mine))})",
            ]
        )
    return markdown_table(
        ["kind", "get a suggestion", "within 1 %", "best match within 1 % (shown or not)"], rows
    )


def methods_table(searched: Sequence[Searched], sift_seconds: Sequence[float]) -> str:
    compared = [s for s in searched if s.grey is not None and s.sift is not None]
    if not compared:
        return "(no scene compared)"
    rows = [
        [
            "template matching in epipolar coordinates, colour (the rule above)",
            *shown(compared, lambda s: s.colour).cells(),
            _best(compared, lambda s: s.colour),
        ],
        [
            "the same, grey photos",
            *shown(compared, lambda s: s.grey).cells(),
            _best(compared, lambda s: s.grey),
        ],
    ]
    for support in SIFT_SUPPORT:
        count = right = 0
        for s in compared:
            assert s.sift is not None
            point, agreeing = s.sift
            if point is not None and agreeing >= support:
                count += 1
                right += float(np.hypot(*(point - s.truth))) <= 0.01 * s.diagonal
        result = Offered(len(compared), count, right)
        rows.append([f"SIFT in the band, {support}+ keypoints agreeing", *result.cells(), "-"])
    table = markdown_table(
        ["method", "get a suggestion", "within 1 %", "best match within 1 % (shown or not)"], rows
    )
    return (
        table + f"\n\nSIFT keypoints of a whole photo: median {np.median(sift_seconds):.2f} s "
        f"({len(sift_seconds)} photos), computed once per photo, not counted per suggestion."
    )


def _best(searched: Sequence[Searched], pick: Callable[[Searched], Timed | None]) -> str:
    found = sum(s.error(pick(s)) <= 0.01 for s in searched)
    return f"{found} ({share(found / len(searched) if searched else math.nan)})"


def flags_table(searched: Sequence[Searched]) -> str:
    checked = [s for s in searched if s.right == s.right]
    rows = []
    for limit in FLAGS:
        name = f"{limit:g} sd" + (" (the rule)" if limit == FLAG_SIGMAS else "")
        rows.append(
            [
                name,
                _flagged(checked, lambda s: s.right, limit),
                _flagged(checked, lambda s: s.swapped, limit),
                _flagged(checked, lambda s: s.moved, limit),
            ]
        )
    return markdown_table(
        [
            "flagged beyond",
            "right taps (the truth, 3 px noise) flagged",
            "another landmark's spot flagged",
            "the truth moved 2-10 % of the diagonal flagged",
        ],
        rows,
    )


def _flagged(checked: Sequence[Searched], value: Callable[[Searched], float], limit: float) -> str:
    flagged = sum(value(s) > limit for s in checked)
    fraction = flagged / len(checked) if checked else math.nan
    return f"{flagged} of {len(checked)} ({share(fraction)})"


def time_table(timed: Sequence[Timed]) -> str:
    rows = []
    for name, values in (
        ("wall", [t.seconds * 1000 for t in timed]),
        ("CPU (process, all threads)", [t.cpu * 1000 for t in timed]),
    ):
        rows.append(
            [
                name,
                ms(percentile(values, 50)),
                ms(percentile(values, 90)),
                ms(percentile(values, 100)),
                ms(float(np.mean(values)) if values else math.nan),
            ]
        )
    return markdown_table(["time per `suggest` call (ms)", "median", "p90", "max", "mean"], rows)
