"""The phone app on a venue's network: how soon a photo can be tapped, how soon it is sent,
how soon an answer reaches the other phone, and how many bytes a whole search moves.

Two phones (Pixel 7 and iPhone 13, emulated in Debian's Chromium, touch input) on a live
server on loopback play the same search (``netbench.search``) on each network profile in
one run: loopback as it is, and a congested venue (1.5 Mbit/s up, 3 Mbit/s down, through
the DevTools protocol's throttling, ``netbench.meter``; 300 ms round trip, through a
loopback proxy that delays both directions of every connection, ``netbench.link``). The
photos are a rendered hall enlarged to 12 MP phone photos; the app shrinks them to 2560 px
before sending, as it does on a phone.

The answer's target is the round trip itself: the last tap goes up, the answer comes down
the other phone's open event stream (1.1 round trips on the venue; 60 ms on loopback).

    .venv/bin/python benchmarks/network.py [--runs N] [--profile NAME ...] [--out PATH]
                                                                    (``make bench-network``)

The report is printed and written as Markdown to ``docs/network-benchmark.md``.
"""

from __future__ import annotations

import json
import statistics
import tempfile
import time
from collections.abc import Callable
from contextlib import ExitStack
from pathlib import Path
from urllib.parse import urlsplit

from netbench.link import Link
from netbench.meter import PROFILES
from netbench.search import PhoneRun, SearchRun, hall_photos, play
from playwright.sync_api import sync_playwright
from report import (
    ROOT,
    command_line,
    heading,
    in_ms,
    in_s,
    log,
    markdown_table,
    publish,
    source_state,
    targets_section,
)

from deploy.replica import serve
from testbed import chromium

DEFAULT_OUT = ROOT / "docs" / "network-benchmark.md"
SEED = 20261125
LANDMARKS = 6
TAPPABLE_MS = 1500.0
# Last tap -> answer drawn on the other phone: on loopback, a fixed budget for the phones'
# and the server's own work; on a network, 1.1 of its round trips (the tap up, the answer
# down, and a tenth for that work).
LOOPBACK_ANSWER_MS = 60.0
ROUND_TRIPS = 1.1
SEARCH_BYTES = 2.5e6


def answer_target_ms(profile: str) -> float:
    round_trip = PROFILES[profile].round_trip_ms
    return ROUND_TRIPS * round_trip if round_trip else LOOPBACK_ANSWER_MS


def run(runs: int, profiles: list[str]) -> list[SearchRun]:
    results: list[SearchRun] = []
    with (
        tempfile.TemporaryDirectory() as folder,
        serve(Path(folder)) as server,
        sync_playwright() as playwright,
        chromium.launch(playwright) as browser,
        ExitStack() as links,
    ):
        port = urlsplit(server.base_url).port
        assert port is not None
        # Each profile's way to the server: the round trip in a link, or loopback itself.
        urls = {
            name: links.enter_context(Link(port, PROFILES[name].round_trip_ms)).base_url
            if PROFILES[name].round_trip_ms
            else server.base_url
            for name in profiles
        }
        photos = hall_photos(Path(folder), SEED, LANDMARKS)
        for index in range(runs):
            for name in profiles:
                log(f"[{name}] search {index + 1} of {runs}")
                results.append(play(browser, playwright, urls[name], PROFILES[name], photos))
    return results


def _phones(results: list[SearchRun]) -> list[tuple[str, list[PhoneRun]]]:
    return [
        ("starter (Pixel 7)", [r.starter for r in results]),
        ("joiner (iPhone 13)", [r.joiner for r in results]),
    ]


def _range(values: list[float], unit: Callable[[float], str]) -> str:
    """The median, and the range when there are several."""
    if len(values) == 1:
        return unit(values[0])
    return f"{unit(statistics.median(values))} ({unit(min(values))}-{unit(max(values))})"


def _mb(count: float) -> str:
    return f"{count / 1e6:.2f} MB"


# Each phone's columns: the header, its measure of one run, and how it is written.
PHONE_COLUMNS: tuple[tuple[str, Callable[[PhoneRun], float], Callable[[float], str]], ...] = (
    ("photo chosen -> tappable", lambda r: r.tappable_ms, in_s),
    ("photo chosen -> uploaded", lambda r: r.uploaded_ms, in_s),
    ("sent", lambda r: float(r.sent), _mb),
    ("received", lambda r: float(r.received), _mb),
)
# Where the answer's time goes: each column's header and its field of a search.
ANSWER_PARTS = {
    "tap -> its PUT sent": "tap_to_sent_ms",
    "the PUT in the app": "server_ms",
    "PUT sent -> answer's event at the other phone": "sent_to_event_ms",
    "event -> answer drawn": "event_to_drawn_ms",
}


def report(results: list[SearchRun], profiles: list[str], seconds: float) -> str:
    rows = []
    checks = []
    for name in profiles:
        mine = [r for r in results if r.profile == name]
        for phone, runs in _phones(mine):
            columns = [
                _range([measure(r) for r in runs], show) for _, measure, show in PHONE_COLUMNS
            ]
            rows.append([name, phone, *columns])
            tappable = max(r.tappable_ms for r in runs)
            checks.append(
                (
                    f"{name}, {phone}: photo chosen -> tappable <= {in_s(TAPPABLE_MS)}",
                    tappable <= TAPPABLE_MS,
                )
            )
            whole = max(r.sent + r.received for r in runs)
            checks.append(
                (f"{name}, {phone}: a whole search <= {_mb(SEARCH_BYTES)}", whole <= SEARCH_BYTES)
            )
        text = [r.answer_text_ms for r in mine]
        drawn = [r.answer_drawn_ms for r in mine]
        answer = [f"text {_range(text, in_ms)}", f"drawn {_range(drawn, in_ms)}", "", ""]
        rows.append([name, "joiner: last tap -> answer", *answer])
        target = answer_target_ms(name)
        within = f"{ROUND_TRIPS:g} round trips, " if PROFILES[name].round_trip_ms else ""
        checks.append(
            (
                f"{name}: last tap -> answer drawn on the other phone <= {within}"
                f"{in_ms(target)} (slowest of {len(drawn)}: {in_ms(max(drawn))})",
                max(drawn) <= target,
            )
        )
    table = markdown_table(["profile", "phone", *(header for header, _, _ in PHONE_COLUMNS)], rows)
    kinds = sorted({k for r in results for p in (r.starter, r.joiner) for k in p.by_kind})
    by_kind = markdown_table(
        ["profile", "phone", *kinds],
        [
            [
                name,
                phone,
                *(
                    _mb(statistics.median([float(r.by_kind.get(k, 0)) for r in runs]))
                    for k in kinds
                ),
            ]
            for name in profiles
            for phone, runs in _phones([r for r in results if r.profile == name])
        ],
    )
    spent = markdown_table(
        ["profile", *ANSWER_PARTS],
        [
            [
                name,
                *(
                    _range([getattr(r, part) for r in results if r.profile == name], in_ms)
                    for part in ANSWER_PARTS.values()
                ),
            ]
            for name in profiles
        ],
    )
    lines = [
        *heading("The phone app on a venue's network", "benchmarks/network.py", "bench-network"),
        f"- {source_state('backend', 'shared_solver', 'frontend')}",
        f"- {len(results)} searches ({len(results) // len(profiles)} per profile), "
        f"{seconds:.0f} s; figures are medians, with the range in brackets",
        "- Profiles, each phone: "
        + "; ".join(f"{n}: {PROFILES[n].describe()}" for n in profiles)
        + ". The throughput through Chromium's `Network.emulateNetworkConditions`; the round "
        "trip through a loopback proxy delaying each direction of every connection by half of "
        "it, and a new connection's first bytes by one more (`benchmarks/netbench/link.py`: "
        "Chromium's own latency delays responses only, so a request and an open event "
        "stream's events would cross without it).",
        f"- One search: the starter (Pixel 7) marks the joiner (iPhone 13) and both tap "
        f"{LANDMARKS} landmarks of a rendered hall (`testbed.venue`), each photo a 12 MP JPEG "
        "the app shrinks to 2560 px; the joiner taps as soon as its photo shows; the starter's "
        "last tap renews the joiner's answer.",
        "- Tappable: the photo view shows the photo, from the file input's change. Uploaded: "
        "the photo's PUT answered. Answer: from the starter's last tap (its finger lifting: the "
        "tap is placed then) to the joiner's screen showing the new position (text) and its "
        "drawing (drawn), each in ms; before that tap both phones have nothing on its way (as "
        "after a person's look at the screen: a suggested spot searched for meanwhile takes "
        "the server's CPU from the answer's). Bytes: on the "
        "wire, as Chromium's `Network` events report them, from opening the app to the last "
        "answer.",
        "",
        table,
        "",
        "Where the answer's time goes (the starter's Chromium stamps its PUT's departure and the "
        "joiner's the event's arrival, on one clock; the app's own time is its Server-Timing):",
        "",
        spent,
        "",
        "Received bytes by what was fetched:",
        "",
        by_kind,
        "",
        *targets_section(checks),
    ]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = command_line(__doc__, DEFAULT_OUT)
    parser.add_argument("--runs", type=int, default=3, help="searches per profile")
    parser.add_argument(
        "--profile", action="append", choices=sorted(PROFILES), help="default: every profile"
    )
    args = parser.parse_args()
    profiles = args.profile or list(PROFILES)
    started = time.monotonic()
    results = run(args.runs, profiles)
    publish(report(results, profiles, time.monotonic() - started), args.out)
    print(json.dumps({r.profile: round(r.answer_drawn_ms) for r in results}))


if __name__ == "__main__":
    main()
