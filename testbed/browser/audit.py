"""The accessibility audit of a phone's page: axe-core (the locked dev dependency,
frontend/node_modules/axe-core), put into the page and run there, the same in both engines.

The audit checks WCAG 2.0, 2.1 and 2.2 at levels A and AA and axe's best practices; the page
fails on what axe rates serious or critical (a control without a name, text without enough
contrast, ...), and the failure lists each violation by rule, impact, element and help.
"""

from __future__ import annotations

import json
import os
import time
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .phone import Phone

AXE = Path(__file__).parents[2] / "frontend" / "node_modules" / "axe-core" / "axe.min.js"
TAGS = ["wcag2a", "wcag2aa", "wcag21a", "wcag21aa", "wcag22aa", "best-practice"]
FAILING = ("serious", "critical")


@cache
def _inject() -> str:
    """A function expression that defines ``window.axe`` once per page. The source is part of
    the script the driver runs (not a script element or eval), so the app's Content Security
    Policy, which allows neither, does not stop it."""
    source = AXE.read_text()
    return f"() => {{ if (!window.axe) {{ {source}\n }} return typeof window.axe; }}"


# One run of axe over the whole document: the violations, reduced to what a reader needs,
# and what axe could not decide ("incomplete": text over the photo, whose contrast it cannot
# compute), by rule and count.
RUN = r"""async (tags) => {
  const results = await axe.run(document, {
    runOnly: { type: "tag", values: tags },
    resultTypes: ["violations", "incomplete"],
  });
  const brief = (v) => ({
    id: v.id, impact: v.impact, help: v.help,
    targets: v.nodes.map((n) => n.target.join(" ")),
  });
  return { violations: results.violations.map(brief), incomplete: results.incomplete.map(brief) };
}"""

PRESENT = "() => typeof window.axe"


def results(phone: Phone) -> dict[str, list[dict[str, Any]]]:
    """What axe finds on the phone's page now: ``violations`` of every impact, and what it
    could not decide (``incomplete``)."""
    if phone.evaluate(PRESENT) != "object":
        assert phone.evaluate(_inject()) == "object", f"{phone}: axe-core did not load"
    found: dict[str, list[dict[str, Any]]] = phone.evaluate(RUN, TAGS)
    return found


def describe(found: list[dict[str, Any]]) -> str:
    """One line per violation: rule id, impact, the elements (CSS selectors) and axe's help."""
    return "\n".join(
        f"  {v['id']} ({v['impact']}): {', '.join(v['targets'])}: {v['help']}" for v in found
    )


def audit(phone: Phone, screen: str) -> None:
    """Fail if the page has a serious or critical violation, listing them all. With
    ``AXE_LOG`` set to a file, all it found (violations of any impact, and what it could not
    decide) is also appended to it, one JSON line per screen (docs/app.md's figures)."""
    started = time.perf_counter()
    found = results(phone)
    if log := os.environ.get("AXE_LOG"):
        took = round(time.perf_counter() - started, 3)
        record = {"phone": str(phone), "screen": screen, "seconds": took, **found}
        with open(log, "a") as lines:
            lines.write(json.dumps(record) + "\n")
    serious = [v for v in found["violations"] if v["impact"] in FAILING]
    assert not serious, f"{phone}, {screen}: axe found\n{describe(serious)}"
