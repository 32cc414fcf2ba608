"""The slow-phone benchmark's report (``benchmarks/slow_phone.py``) from made-up runs: each
target judged on the slow rate's worst figure, its peer's beside it, and the JavaScript
counted from the files the phone fetched. No browser: the benchmark itself drives one for
about 30 s at its smallest on a loaded machine, too long for ``make test``; it is run by
``make bench-slow-phone``."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[2] / "benchmarks"))

import slow_phone
from slowphone.play import PhoneRun, SlowestEvent, Tap

TEMPLE = "temple PNG 640 x 480"
LOAD = ("1.00 1.00 1.00", "1.20 1.00 1.00", 0.5)


def phone_run(rate: float, tappable_ms: float, tap_ms: float) -> PhoneRun:
    slowest = SlowestEvent("pointerdown", waited=2.0, handlers=3.0, duration=tap_ms)
    return PhoneRun(
        rate,
        TEMPLE,
        start_screen_ms=300.0 * rate,
        tappable_ms=tappable_ms,
        taps=[Tap(tap_ms, tap_ms - 1, slowest), Tap(tap_ms / 2, tap_ms / 2, None)],
        start_scripts={"/assets/index.js"},
        scripts={"/assets/index.js", "/assets/tap.js"},
    )


def opening(drawn_ms: float) -> dict[str, float]:
    """Show me's steps, ms after the tap, its first marker drawn at ``drawn_ms``."""
    return {
        "view-opened": 30.0,
        "camera-started": 40.0,
        "first-frame": drawn_ms - 10,
        "marker-drawn": drawn_ms,
    }


# The first opening fetches the view's code: the slowest.
OPENED = {1.0: [opening(300.0), opening(200.0)], 4.0: [opening(900.0), opening(400.0)]}


def dist(tmp_path: Path) -> Path:
    """A build of three scripts, one of which no screen fetches."""
    for name, body in (("index.js", "a" * 5000), ("tap.js", "b" * 5000), ("later.js", "c")):
        (tmp_path / "assets").mkdir(exist_ok=True)
        (tmp_path / "assets" / name).write_text(body)
    return tmp_path


def test_targets_are_judged_on_the_slow_rates_worst_run(tmp_path: Path) -> None:
    runs = [phone_run(1.0, 300.0, 20.0), phone_run(4.0, 900.0, 80.0)]
    runs += [phone_run(1.0, 400.0, 30.0), phone_run(4.0, 2100.0, 60.0)]
    text = slow_phone.report(runs, [TEMPLE], 10.0, LOAD, OPENED, dist=dist(tmp_path))
    targets = text.split("## Targets", 1)[1]
    assert (
        f"- FAIL: CPU 4x, {TEMPLE}: photo chosen -> tappable <= 2.00 s (worst of 2: 2.10 s; "
        "median 1.50 s, not throttled 0.35 s)"
    ) in targets
    assert "- PASS: CPU 4x: a tap -> its mark painted <= 100 ms (worst of 4: 80 ms;" in targets
    assert "- PASS: JavaScript fetched for the start and tap screens <= 70 kB gzipped" in targets
    assert "in 2 files; the whole build" in targets
    assert "in 3 files)" in targets
    assert f"| {TEMPLE} | 4x | 1.50 s (2.10 s) | 50 ms (80 ms) |" in text
    assert "| 4x | 2 of 4 | pointerdown 2 | 2 ms (2 ms) | 3 ms (3 ms) |" in text
    assert "load average 1.00 1.00 1.00 before the run, 1.20 1.00 1.00 after" in text
    assert (
        "- PASS: CPU 4x: Show me's first marker drawn <= 1000 ms after the tap (worst of 2: "
        "900 ms; median 650 ms, not throttled 250 ms)"
    ) in targets
    assert (
        "| 4x | 900 ms | 30 ms (30 ms) | 40 ms (40 ms) | 390 ms (390 ms) | 400 ms (400 ms) |"
        in text
    )


def test_a_slow_tap_fails_its_target(tmp_path: Path) -> None:
    runs = [phone_run(1.0, 300.0, 20.0), phone_run(4.0, 900.0, 180.0)]
    opened = {**OPENED, 4.0: [opening(1100.0), opening(400.0)]}
    text = slow_phone.report(runs, [TEMPLE], 10.0, LOAD, opened, dist=dist(tmp_path))
    assert "- FAIL: CPU 4x: a tap -> its mark painted <= 100 ms (worst of 2: 180 ms;" in text
    assert "| a tap -> its mark painted | 15 ms | 135 ms | 9.0x |" in text
    assert (
        "- FAIL: CPU 4x: Show me's first marker drawn <= 1000 ms after the tap (worst of 2:" in text
    )
