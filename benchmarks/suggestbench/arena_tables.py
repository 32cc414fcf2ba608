"""The suggestion benchmark's tables of the arenas (:mod:`.arenas`), and its targets."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from report import markdown_table, verdict

from shared_solver.matching.suggestion import RULES, Evidence, leads

from .arenas import FOUND, SIGMAS, ArenaRun, Asked
from .tables import FAR, IN_CODE, Offered, Rule, by_rule, offers, share, shown
from .trials import BEFORE, Searched, Timed

# The targets, on the evaluation arenas over every noise: of the spots offered, at
# least 95 % within 1 % of the diagonal and none beyond 3 %; at least 25 % of landmarks
# offered one.
TARGET_RIGHT = 0.95  # and none beyond tables.FAR
TARGET_OFFERED = 0.25
# The rule's thresholds tried on the calibration scenes: least score, least margin.
SCORES = (0.5, 0.6, 0.7, 0.8)
MARGINS = (0.0, 0.03, 0.05, 0.08)
# Least leads of a match in another view over the patch as read, tried the same way.
VIEW_LEADS = (0.0, 0.1, 0.15, 0.2)
# Stricter least leads over the runner-up, counted on the held-out arenas (trade-off).
STRICTER_MARGINS = (0.06, 0.08, 0.1, 0.15)
# The context's least lead over every other place (infinite: never instead of the
# margin) and its least score, tried the same way.
CONTEXT_MARGINS = (0.05, 0.1, 0.15, 0.2, math.inf)
MIN_CONTEXTS = (-1.0, 0.3, 0.4, 0.5)

HEADER = ["asked", "offered a spot", "within 1 % of the diagonal", "beyond 3 %", "worst"]


def by_rule_before(evidence: Evidence) -> bool:
    """The rule before this change: the match leads (score 0.7, margin 0.05) and the search
    back lands within 1 % of the tap (not how surely, nor in which view)."""
    return leads(evidence.match, BEFORE) and evidence.returned <= BEFORE.tolerance


def now(item: Asked | Searched) -> Timed | None:
    return item.timed if isinstance(item, Asked) else item.colour


def before(item: Asked | Searched) -> Timed | None:
    return item.before if isinstance(item, Asked) else None


def scenes_table(runs: Sequence[ArenaRun]) -> str:
    rows = []
    for stream in ("calibration", "evaluation"):
        mine = [run for run in runs if run.stream == stream]
        if not mine:
            continue
        used = [run for run in mine if run.asked]
        kinds = sorted({kind for run in used for kind in run.kinds})
        per_kind = ", ".join(
            f"{kind} {sum(run.kinds.count(kind) for run in used)}" for kind in kinds
        )
        apart = [run.distance for run in used]
        rows.append(
            [
                stream,
                str(len(mine)),
                str(len(used)),
                f"{min(apart):.0f}-{max(apart):.0f} m" if apart else "-",
                per_kind,
                str(sum(len(run.asked) for run in used)),
                f"{np.median([run.render_seconds for run in mine]):.2f} s",
            ]
        )
    return markdown_table(
        [
            "arenas",
            "rendered",
            "with 10 landmarks both photos show",
            "phones apart",
            "landmarks picked, by kind",
            "landmarks asked for",
            "render time per pair (median)",
        ],
        rows,
    )


def offered_table(asked: Sequence[Asked], rule: Rule = IN_CODE) -> tuple[str, Offered]:
    """Per landmarks found and tap noise, and over all: the headline table."""
    rows = []
    for found in FOUND:
        for sigma in SIGMAS:
            part = [a for a in asked if a.found == found and a.sigma == sigma]
            rows.append([f"{found}", f"{sigma:g} px", *shown(part, now, rule).arena_cells()])
    total = shown(asked, now, rule)
    rows.append(["**all**", "", *[f"**{cell}**" for cell in total.arena_cells()]])
    return markdown_table(["landmarks found", "tap noise", *HEADER], rows), total


def kinds_table(asked: Sequence[Asked], rule: Rule = IN_CODE) -> str:
    rows = []
    for kind in sorted({a.kind for a in asked}):
        mine = [a for a in asked if a.kind == kind]
        best = sum(a.error(a.timed) <= 0.01 for a in mine)
        rows.append(
            [kind, *shown(mine, now, rule).arena_cells(), f"{best} ({share(best / len(mine))})"]
        )
    return markdown_table(["kind", *HEADER, "best place within 1 % (offered or not)"], rows)


def before_table(asked: Sequence[Asked]) -> str:
    """The same landmarks and taps, searched and decided as before and as now."""
    compared = [a for a in asked if a.before is not None or a.timed is None]
    rows = [
        [
            "before: the patch as read; score 0.7, lead 0.05, search back within 1 %",
            *shown(compared, before, by_rule_before).arena_cells(),
        ],
        [
            "the search now, the rule before",
            *shown(compared, now, by_rule_before).arena_cells(),
        ],
        [
            "now, and where the band is wider than `max_across` too",
            *shown(compared, now, by_rule(replace(RULES, max_across=math.inf))).arena_cells(),
        ],
        [
            "now, without the context (the rule before it)",
            *shown(compared, now, by_rule(replace(RULES, context_radius=0))).arena_cells(),
        ],
        ["now (the rule in the code)", *shown(compared, now, IN_CODE).arena_cells()],
    ]
    return markdown_table(["search and rule", *HEADER], rows)


def rule_table(items: Sequence[Asked | Searched]) -> str:
    """Offered / right / beyond 3 % for each least score and margin (the rest as in the
    code)."""
    rows = []
    for score in SCORES:
        cells = [f"{score:g}"]
        for margin in MARGINS:
            rules = replace(RULES, min_score=score, min_margin=margin)
            cells.append(_cell(shown(items, now, by_rule(rules)), rules == RULES))
        rows.append(cells)
    return markdown_table(["least score", *[f"margin {m:g}" for m in MARGINS]], rows)


def view_table(items: Sequence[Asked | Searched]) -> str:
    """Offered / right / beyond 3 % for each least lead of a match in another view than as
    read over the patch as read, and none offered (the rest as in the code)."""
    leads_tried = [*VIEW_LEADS, math.inf]
    cells = []
    for lead in leads_tried:
        rules = replace(RULES, min_view_lead=lead)
        cells.append(_cell(shown(items, now, by_rule(rules)), rules == RULES))
    names = [f"lead {lead:g}" for lead in VIEW_LEADS] + ["none (as read alone)"]
    return markdown_table(names, [cells])


def context_table(items: Sequence[Asked | Searched]) -> str:
    """Offered / right / beyond 3 % for each least score in context and least lead of the
    context over every other place (the rest as in the code)."""
    rows = []
    for least in MIN_CONTEXTS:
        cells = ["none" if least < 0 else f"{least:g}"]
        for margin in CONTEXT_MARGINS:
            rules = replace(RULES, min_context=least, context_margin=margin)
            cells.append(_cell(shown(items, now, by_rule(rules)), rules == RULES))
        rows.append(cells)
    names = [
        f"lead {m:g}" if math.isfinite(m) else "no lead (the margin alone)" for m in CONTEXT_MARGINS
    ]
    return markdown_table(["least score in context", *names], rows)


def tradeoff_table(asked: Sequence[Asked]) -> str:
    """Held out: the rule in the code with a higher least lead over the runner-up (the
    search back was made only for matches that lead under the rule in the code, so only
    stricter rules can be counted)."""
    rows = []
    for margin in sorted({RULES.min_margin, *STRICTER_MARGINS}):
        rules = replace(RULES, min_margin=margin)
        result = shown(asked, now, by_rule(rules))
        name = f"{margin:g}" + (" (the rule)" if rules == RULES else "")
        rows.append([name, *result.arena_cells()])
    return markdown_table(["least lead over the runner-up", *HEADER], rows)


def _cell(result: Offered, chosen: bool) -> str:
    text = f"{share(result.coverage)} / {share(result.precision)} / {result.far}"
    return f"**{text}**" if chosen else text


def far_sources(asked: Sequence[Asked], rule: Rule = IN_CODE) -> tuple[int, int]:
    """(landmarks, arenas) behind the spots offered beyond :data:`.tables.FAR`: one
    landmark looked for in one photo is asked for at every tap noise and count of
    landmarks found, so one look-alike can be offered several times."""
    far = [a for a, error in offers(asked, now, rule) if error > FAR]
    landmarks = {(a.scene, a.direction, *np.round(a.truth, 3).tolist()) for a in far}
    return len(landmarks), len({a.scene for a in far})


def targets(total: Offered, asked: Sequence[Asked]) -> list[str]:
    landmarks, arenas = far_sources(asked)
    return [
        f"- {verdict(total.precision >= TARGET_RIGHT)}: at least "
        f"{100 * TARGET_RIGHT:.0f} % of offered spots within 1 % of the diagonal: "
        f"{total.right} of {total.offered} ({share(total.precision)}).",
        f"- {verdict(total.offered > 0 and total.far == 0)}: none beyond "
        f"{100 * FAR:.0f} % of the diagonal: {total.far} (worst "
        f"{100 * total.worst:.1f} %), of {landmarks} landmarks looked for in "
        f"{arenas} of the {len({a.scene for a in asked})} arenas.",
        f"- {verdict(total.coverage >= TARGET_OFFERED)}: at least "
        f"{100 * TARGET_OFFERED:.0f} % of landmarks offered a spot: {total.offered} of "
        f"{total.asked} ({share(total.coverage)}).",
    ]
