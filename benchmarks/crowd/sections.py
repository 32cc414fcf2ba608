"""The report in Markdown: its sections in order (the calls under load, where the server's
CPU goes, the quiet server) and the whole."""

from __future__ import annotations

from report import markdown_table, ms, percent, percentile

from .findings import EXEMPT, budget, notes, sessions_per_second, steady, streams_held, targets
from .phases import QUIET_SPEED, STREAM
from .preamble import flow_text, header
from .recorder import ENDPOINTS, Recorder
from .run import Results


def endpoint_rows(rec: Recorder) -> list[list[str]]:
    rows = []
    for name in ENDPOINTS:
        calls = rec.calls[name]
        latency, server = calls.latency_ms, calls.server_ms
        rows.append(
            [
                f"`{name}`" + (" (no target)" if name in EXEMPT else ""),
                str(len(latency) + sum(calls.errors.values())),
                ms(percentile(latency, 50)),
                ms(percentile(latency, 95)),
                ms(percentile(latency, 99)),
                ms(max(latency, default=float("nan"))),
                f"{ms(percentile(server, 50))} / {ms(percentile(server, 99))}",
                str(sum(calls.errors.values())),
            ]
        )
    every = [v for name in ENDPOINTS for v in rec.calls[name].latency_ms]
    rows.append(
        [
            "**all calls**",
            str(len(every) + rec.http_errors),
            ms(percentile(every, 50)),
            ms(percentile(every, 95)),
            ms(percentile(every, 99)),
            ms(max(every, default=float("nan"))),
            "",
            str(rec.http_errors),
        ]
    )
    return rows


def endpoint_table(rec: Recorder) -> str:
    return markdown_table(
        [
            "call",
            "calls",
            "p50 (ms)",
            "p95 (ms)",
            "p99 (ms)",
            "max (ms)",
            "Server-Timing p50 / p99 (ms)",
            "errors",
        ],
        endpoint_rows(rec),
    )


def load_section(results: Results) -> list[str]:
    load_ = results.load
    rec = load_.rec
    window, cpu = steady(load_)
    whole_rate, steady_rate = sessions_per_second(load_)
    requests = [s.requests for s in window]
    duration = rec.session_seconds
    fetches = rec.state_fetches_per_phone
    held, open_streams = streams_held(load_)
    events = ", ".join(f"{k} {v}" for k, v in rec.events.items())
    memory = results.server_memory_mb
    lag = rec.loop_lag_ms
    rows = [
        ["sessions started / completed", f"{rec.sessions_started} / {rec.sessions_completed}"],
        [
            "completed sessions per second: whole phase / steady window",
            f"{whole_rate:.2f} / {steady_rate:.2f}",
        ],
        [
            "session duration p50 / p95 / max (s)",
            f"{percentile(duration, 50):.1f} / {percentile(duration, 95):.1f} / "
            f"{max(duration, default=float('nan')):.1f}",
        ],
        [
            "sessions in flight: steady median / peak",
            f"{held:.0f} / {max(s.sessions for s in rec.samples)}",
        ],
        [
            "event streams open: steady median / peak",
            f"{open_streams:.0f} / {max(s.streams for s in rec.samples)}",
        ],
        [
            "calls in flight (streams aside): steady median / peak",
            f"{percentile(requests, 50):.0f} / {max(requests, default=0)}",
        ],
        [
            "events received per stream",
            f"{sum(rec.events.values()) / max(rec.streams_opened, 1):.1f} ({events})",
        ],
        [
            "state fetches per phone: median / max",
            f"{percentile(fetches, 50):.0f} / {max(fetches, default=0)}",
        ],
        [
            "CPU in the steady window, cores: server / load generator / anything else",
            f"{cpu.server:.2f} / {cpu.client:.2f} / {cpu.others:.2f} "
            f"(machine {percent(cpu.machine)} busy)",
        ],
        [
            "server peak memory (VmHWM)",
            " + ".join(f"{m:.0f} MB" for m in memory)
            + (f" ({len(memory)} processes under uvicorn's supervisor)" if len(memory) > 1 else ""),
        ],
        [
            "load generator's event loop lag p50 / p99 / max (ms)",
            f"{ms(percentile(lag, 50))} / {ms(percentile(lag, 99))} / "
            f"{ms(max(lag, default=float('nan')))}",
        ],
        [
            "errors: failed calls / flow errors",
            f"{rec.http_errors} / {sum(rec.flow_errors.values())}",
        ],
    ]
    lines = [
        "## Under load",
        f"{load_.concurrency} sessions at once, so up to {2 * load_.concurrency} event "
        "streams. The steady window runs from the end of the ramp to the last session start "
        f"({load_.stopped_at - load_.steady_from:.0f} s). Latency is the client's: request "
        "sent to response read (for the stream: to its headers), measured in the load "
        "generator, so it includes the load generator's own delays (its event loop lag, "
        "below). Server-Timing is the app's time from the request's arrival to its "
        "response's start (not the time a request waits in uvicorn before the app sees it).",
        endpoint_table(rec),
        markdown_table(["measured", "value"], rows),
    ]
    return lines + error_kinds(rec)


def error_kinds(rec: Recorder) -> list[str]:
    """The table of what failed, if anything did."""
    if not rec.errors:
        return []
    kinds = [
        [f"`{name}`", kind, str(count)]
        for name in ENDPOINTS
        for kind, count in rec.calls[name].errors.most_common()
    ] + [["(flow)", kind, str(count)] for kind, count in rec.flow_errors.most_common()]
    return ["Errors by kind:", markdown_table(["call", "error", "count"], kinds)]


def cost_section(results: Results) -> list[str]:
    model = budget(results)
    rows = [
        [f"`{name}`" if name != STREAM else name, ms(cost), f"{count:.1f}", ms(cost * count)]
        for name, cost, count in model.rows
    ]
    rows.append(
        [
            "both streams polling the event table",
            "",
            "",
            ms(model.polling_ms),
        ]
    )
    rows.append(["**modelled total**", "", "", f"**{ms(model.modelled_ms)}**"])
    rows.append(["measured: a quiet session, everything", "", "", ms(model.measured_ms)])
    lines = [
        "## Where the server's CPU goes",
        f"Server CPU per call, each call alone ({results.costs.calls} of each, one at a time, "
        "from /proc: the HTTP layer included), times the calls one session makes on a quiet "
        f"server ({results.solo.sessions} sessions, below); event-stream polling from the "
        f"idle streams, over a session's median length under load, "
        f"{model.session_seconds:.1f} s. Failed calls "
        f"while measuring: {results.costs.failed}.",
        markdown_table(
            ["call", "server CPU per call (ms)", "calls per session", "CPU per session (ms)"],
            rows,
        ),
    ]
    idle_ = results.idle
    if idle_ is not None:
        per_stream_ms = 1000 * idle_.cpu.server / max(idle_.streams, 1)
        lines.append(
            f"Idle streams: {idle_.streams // 2} sessions paired with both streams open "
            f"({idle_.streams} streams) and nobody tapping, for {idle_.cpu.seconds:.1f} s: "
            f"the server used {idle_.cpu.server:.3f} cores, {per_stream_ms:.3f} ms of CPU per "
            f"stream per second (each stream re-reads the event table every "
            f"{idle_.poll_seconds:g} s); the load generator {idle_.cpu.client:.3f} cores, "
            f"anything else {idle_.cpu.others:.3f}; errors: {idle_.rec.errors}."
        )
    return lines


def quiet_section(results: Results) -> list[str]:
    solo_ = results.solo
    rec = solo_.rec
    return [
        "## Quiet server",
        f"{solo_.sessions} sessions one at a time (the same flow, pauses {QUIET_SPEED:g} "
        "times shorter): each call's "
        f"time without queueing. Sessions completed: {rec.sessions_completed}; errors: "
        f"{rec.errors}; CPU meanwhile, cores: server {solo_.cpu.server:.2f}, load generator "
        f"{solo_.cpu.client:.2f}, anything else {solo_.cpu.others:.2f}.",
        endpoint_table(rec),
        *error_kinds(rec),
    ]


def report(results: Results) -> str:
    spent = ", ".join(f"{name} {s:.1f} s" for name, s in results.timings.items())
    sections = [
        header(results),
        flow_text(),
        "## Targets",
        "\n".join(f"- {line}" for line in targets(results)),
        *load_section(results),
        "What the figures say:",
        "\n".join(f"- {line}" for line in notes(results)),
        *cost_section(results),
        *quiet_section(results),
        f"Wall time: {sum(results.timings.values()):.1f} s ({spent}; interpreter start-up "
        "and imports not included).",
    ]
    return "\n\n".join(sections) + "\n"
