"""The phone app on a slow phone: how soon a picked photo takes taps, how soon a tap shows,
and how much JavaScript a phone downloads, with Chromium's CPU throttled 4x.

One phone (a Pixel 7, emulated in Debian's Chromium, touch input) on a live server on
loopback opens the start screen, joins a session through its link, picks a photo and taps
landmarks on it (``slowphone.play``); each moment is stamped inside the page
(``slowphone.watch``). Every run is on a fresh phone (nothing cached). Its peer in the same
run, interleaved with it: the same runs with the CPU as it is (rate 1), so that the report
shows what the throttling costs on this machine. Photos: the temple (640 x 480 PNG) and a
12 MP JPEG made from it, as a phone's camera gives one (``slowphone.photos``).

    .venv/bin/python benchmarks/slow_phone.py [--runs N] [--photo NAME ...] [--out PATH]
                                                                  (``make bench-slow-phone``)

The report is printed and written as Markdown to ``docs/slow-phone.md``.
"""

from __future__ import annotations

import json
import os
import statistics
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path

from playwright.sync_api import sync_playwright
from report import (
    ROOT,
    command_line,
    heading,
    in_ms,
    in_s,
    log,
    machine,
    machine_cpu_seconds,
    markdown_table,
    percent,
    publish,
    source_state,
    targets_section,
)
from slowphone import size
from slowphone.photos import NAMES, photo
from slowphone.play import MODEL, SPOTS, PhoneRun, SlowestEvent, Tap, play
from slowphone.showme import openings

from deploy.replica import serve
from testbed import chromium
from testbed.opening import STEPS

DEFAULT_OUT = ROOT / "docs" / "slow-phone.md"
SEED = 20261127
SLOW = 4.0  # the slow phone: Chromium's CPU throttling at 4x
RATES = (1.0, SLOW)  # the peer first: this machine's CPU as it is
TAPPABLE_MS = 2000.0
TAP_MS = 100.0
SHOW_ME_MS = 1000.0  # the live view's issue: the marker drawn <= 1 s after the tap
JS_KB = 70.0
# The app's code under test, the build's dependencies' folder aside (a worktree may link it).
CODE = ("backend", "shared_solver", "frontend", ":(exclude)frontend/node_modules")


Openings = dict[float, list[dict[str, float]]]


def run(runs: int, chosen: dict[str, Path], count: int) -> tuple[list[PhoneRun], Openings]:
    """``runs`` rounds, each every photo at every rate, interleaved; then ``count``
    openings of Show me at every rate, each rate on a phone of its own."""
    results: list[PhoneRun] = []
    opened: Openings = {}
    with (
        tempfile.TemporaryDirectory() as folder,
        serve(Path(folder)) as server,
        sync_playwright() as playwright,
    ):
        with chromium.launch(playwright) as browser:
            for index in range(runs):
                for name, path in chosen.items():
                    for rate in RATES:
                        log(f"[{name}, CPU {rate:g}x] run {index + 1} of {runs}")
                        url = server.base_url
                        results.append(play(playwright, browser, url, rate, (name, path)))
        for rate in RATES:
            log(f"[Show me, CPU {rate:g}x] {count} openings")
            opened[rate] = openings(playwright, server.base_url, rate, count)
    return results, opened


def _spread(values: Sequence[float], show: Callable[[float], str] = in_ms) -> str:
    """Median (worst); "-" when there are none."""
    if not values:
        return "-"
    return f"{show(statistics.median(values))} ({show(max(values))})"


def _files(count: int) -> str:
    return f"{count} file" + ("s" if count != 1 else "")


def _rate(rate: float) -> str:
    return f"{rate:g}x" if rate != 1 else "1x (not throttled)"


def _taps(results: list[PhoneRun]) -> list[Tap]:
    return [tap for r in results for tap in r.taps]


# The times table's columns after the photo and the rate: each one's header, its figures in
# some runs, and how they are written.
TIMES: tuple[tuple[str, Callable[[list[PhoneRun]], list[float]], Callable[[float], str]], ...] = (
    ("photo chosen -> tappable", lambda runs: [r.tappable_ms for r in runs], in_s),
    ("a tap -> its mark painted", lambda runs: [t.down_ms for t in _taps(runs)], in_ms),
    ("finger lifted -> painted", lambda runs: [t.lifted_ms for t in _taps(runs)], in_ms),
    ("start screen painted", lambda runs: [r.start_screen_ms for r in runs], in_ms),
)
# The parts of a tap's slowest event, ms.
SLOWEST: dict[str, Callable[[SlowestEvent], float]] = {
    "its wait for the main thread": lambda e: e.waited,
    "its handlers": lambda e: e.handlers,
    "then to the next paint": lambda e: e.duration - e.waited - e.handlers,
    "its duration": lambda e: e.duration,
}


def times_table(results: list[PhoneRun], names: list[str]) -> str:
    rows = []
    for name in names:
        for rate in RATES:
            mine = [r for r in results if r.photo == name and r.rate == rate]
            spreads = [_spread(measure(mine), show) for _, measure, show in TIMES]
            rows.append([name, _rate(rate), *spreads])
    return markdown_table(["photo", "CPU", *(header for header, _, _ in TIMES)], rows)


def cost_table(results: list[PhoneRun], names: list[str]) -> str:
    """Medians at 1x and at the slow rate, and their ratio."""

    def row(what: str, measure: Callable[[list[PhoneRun]], list[float]]) -> list[str]:
        fast, slow = (
            statistics.median(measure([r for r in results if r.rate == rate]))
            for rate in (1.0, SLOW)
        )
        return [what, in_ms(fast), in_ms(slow), f"{slow / fast:.1f}x"]

    def tappable(name: str) -> Callable[[list[PhoneRun]], list[float]]:
        return lambda runs: [r.tappable_ms for r in runs if r.photo == name]

    rows = [row(f"photo chosen -> tappable, {name}", tappable(name)) for name in names]
    rows.append(row("a tap -> its mark painted", lambda runs: [t.down_ms for t in _taps(runs)]))
    return markdown_table(["what", "1x", f"{SLOW:g}x", "ratio"], rows)


def events_table(results: list[PhoneRun]) -> str:
    """Each tap's slowest event in the browser's Event Timing, by rate."""
    rows = []
    for rate in RATES:
        taps = _taps([r for r in results if r.rate == rate])
        slowest = [t.slowest for t in taps if t.slowest is not None]
        names = sorted({e.name for e in slowest})
        rows.append(
            [
                _rate(rate),
                f"{len(slowest)} of {len(taps)}",
                ", ".join(f"{n} {sum(e.name == n for e in slowest)}" for n in names) or "-",
                *(_spread([part(e) for e in slowest]) for part in SLOWEST.values()),
            ]
        )
    header = ["CPU", "taps with an event >= 16 ms", "slowest event", *SLOWEST]
    return markdown_table(header, rows)


def show_me_table(opened: Openings) -> str:
    """Show me's openings by rate: the first (the view's code fetched), then the others'
    steps, median (worst)."""
    rows = []
    for rate, steps in opened.items():
        first, rest = steps[0], steps[1:]
        rows.append(
            [
                _rate(rate),
                in_ms(first["marker-drawn"]),
                *(_spread([s[step] for s in rest]) for step in STEPS),
            ]
        )
    return markdown_table(
        [
            "CPU",
            "first opening: marker drawn",
            *(f"then: {step.replace('-', ' ')}" for step in STEPS),
        ],
        rows,
    )


def report(
    results: list[PhoneRun],
    names: list[str],
    seconds: float,
    load: tuple[str, str, float],
    opened: Openings,
    *,
    dist: Path = size.DIST,
) -> str:
    """The report of ``results`` (every photo of ``names`` at every rate), the JavaScript
    sizes from the build in ``dist``, the machine's ``load`` (load averages before and
    after, the cores' busy fraction)."""
    start_js = size.of(set().union(*(r.start_scripts for r in results)), dist)
    loaded_js = size.of(set().union(*(r.scripts for r in results)), dist)
    every_js = size.every(dist)
    js = markdown_table(
        ["JavaScript", "files", "gzipped"],
        [
            [what, str(part.files), f"{part.kb:.1f} kB"]
            for what, part in (
                ("fetched for the start screen", start_js),
                ("fetched for the start and tap screens", loaded_js),
                ("every file of the build", every_js),
            )
        ],
    )
    slow = [r for r in results if r.rate == SLOW]
    fast = [r for r in results if r.rate == 1]

    def check(
        what: str,
        limit: float,
        slow: list[float],
        fast: list[float],
        *,
        show: Callable[[float], str] = in_ms,
        after: str = "",
    ) -> tuple[str, bool]:
        """The slow rate's worst within ``limit``; its median and its peer's beside it."""
        return (
            f"CPU {SLOW:g}x{what} <= {show(limit)}{after} (worst of {len(slow)}: "
            f"{show(max(slow))}; median {show(statistics.median(slow))}, not throttled "
            f"{show(statistics.median(fast))})",
            max(slow) <= limit,
        )

    checks = [
        check(
            f", {name}: photo chosen -> tappable",
            TAPPABLE_MS,
            [r.tappable_ms for r in slow if r.photo == name],
            [r.tappable_ms for r in fast if r.photo == name],
            show=in_s,
        )
        for name in names
    ]
    checks += [
        check(
            ": a tap -> its mark painted",
            TAP_MS,
            [t.down_ms for t in _taps(slow)],
            [t.down_ms for t in _taps(fast)],
        ),
        check(
            ": Show me's first marker drawn",
            SHOW_ME_MS,
            [s["marker-drawn"] for s in opened[SLOW]],
            [s["marker-drawn"] for s in opened[1.0]],
            after=" after the tap",
        ),
        (
            f"JavaScript fetched for the start and tap screens <= {JS_KB:g} kB gzipped "
            f"({loaded_js.kb:.1f} kB in {_files(loaded_js.files)}; the whole build "
            f"{every_js.kb:.1f} kB in {_files(every_js.files)})",
            loaded_js.kb <= JS_KB,
        ),
    ]
    before, after, busy = load
    runs = len(results) // (len(names) * len(RATES))
    lines = [
        *heading(
            "A slow phone: the app with its CPU throttled 4x",
            "benchmarks/slow_phone.py",
            "bench-slow-phone",
        ),
        f"- Code: {source_state(*CODE)}; the app as built in `frontend/dist`",
        machine(
            f"; load average {before} before the run, {after} after; the cores "
            f"{percent(busy)} busy during it (this run's browser and server included)"
        ),
        f"- {len(results)} runs in {seconds:.0f} s: {runs} per photo and CPU rate, the rates "
        f"interleaved, each on a fresh {MODEL} (nothing cached); {len(SPOTS)} taps per run. "
        "Figures are medians, the worst in brackets.",
        f"- Slow: Chromium's CPU throttling at {SLOW:g}x (`Emulation.setCPUThrottlingRate`), "
        "set before the app loads. Its peer: the same runs at 1x, this machine's CPU as it is.",
        "- Tappable: from the file input's `change` to the frame after the photo view "
        "published its transform (`data-scale`) and its picture fired `load`. A tap: from the "
        "finger's `pointerdown` (the event's time stamp) to the frame after the new landmark "
        "mark is in the page, its paint past (a `requestAnimationFrame` callback, then the "
        "task after it); the taps come after the photo's upload ended, as after a person's "
        "look at it. Start screen: its first contentful paint, from the navigation. All "
        "stamped on the page's own clock; the benchmark waits on a promise the page resolves, "
        "not by polling it.",
        "- What this is not: a phone. Chromium's throttling stretches the page's main thread "
        "only; image decoding and rasterisation on other threads, the browser's other "
        "processes and the network run at this machine's speed, without a GPU "
        "(`--disable-gpu`). A phone's slower memory, its heat limits and its image decoders "
        "are not modelled. On a shared machine, other work stretches both rates' figures.",
        "",
        times_table(results, names),
        "",
        "What the throttling costs on this machine (medians):",
        "",
        cost_table(results, names),
        "",
        "Where a tap's time goes, as the browser's Event Timing measured each tap's slowest "
        "event (Interaction to Next Paint's parts; the browser reports events of 16 ms and "
        "more, durations rounded to 8 ms):",
        "",
        events_table(results),
        "",
        "Show me's opening (`slowphone/showme.py`): a phone that took its photo in the app "
        "(Chromium's fake camera filming the temple photo at 30 frames a second, the "
        "sensors held still through the DevTools protocol) and found three landmarks opens "
        "the live view and closes it again, the CPU throttled from the first opening on; "
        "each step from the tap on Show me (its click's time stamp) to the app's marks: the "
        "view mounted, the camera's stream given, its first frame loaded, the first marker "
        "drawn over the video. The first opening fetches and compiles the view's code. Not "
        "modelled: a phone's camera starting (the fake camera starts at this machine's "
        "speed and delivers its first frame a frame's time after the stream).",
        "",
        show_me_table(opened),
        "",
        "The app's JavaScript, each file gzipped at level 9 from `frontend/dist` (those the "
        "phone fetched from `/assets`, every run's together; a service worker's precaching "
        "is not a page's fetch):",
        "",
        js,
        "",
        *targets_section(checks),
    ]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = command_line(__doc__, DEFAULT_OUT)
    parser.add_argument("--runs", type=int, default=5, help="runs per photo and CPU rate")
    parser.add_argument("--photo", action="append", choices=list(NAMES), help="default: both")
    parser.add_argument("--openings", type=int, default=10, help="Show me's, per CPU rate")
    args = parser.parse_args()
    started = time.monotonic()
    before = " ".join(f"{v:.2f}" for v in os.getloadavg())
    busy0, total0 = machine_cpu_seconds()
    with tempfile.TemporaryDirectory() as folder:
        chosen = {NAMES[p]: photo(p, Path(folder), SEED) for p in args.photo or NAMES}
        results, opened = run(args.runs, chosen, args.openings)
    busy1, total1 = machine_cpu_seconds()
    after = " ".join(f"{v:.2f}" for v in os.getloadavg())
    load = (before, after, (busy1 - busy0) / (total1 - total0))
    publish(report(results, list(chosen), time.monotonic() - started, load, opened), args.out)
    summary = {
        f"{r.photo}, {r.rate:g}x": [round(r.tappable_ms), round(max(t.down_ms for t in r.taps))]
        for r in results
    }
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
