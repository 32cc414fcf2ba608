"""What the figures say: the run's state over its steady window, the server CPU a session
costs, the targets met or not, and the notes on what limited the run."""

from __future__ import annotations

from dataclasses import dataclass

from report import ms, percent, percentile, verdict

from .phases import STREAM, Load
from .recorder import ENDPOINTS, PHOTO, Sample
from .run import Results
from .server import CORES, CpuUse

LATENCY_TARGET_MS = 500.0  # p99 of every call but the photo upload
EXEMPT = {PHOTO}  # not held to the p99 target
STREAMS_HELD = 0.9  # of the 2N streams open (steady median), for the concurrency target
BUSY_MACHINE_CORES = 0.1  # other programs using more than this spoil the comparison


def steady(load_: Load) -> tuple[list[Sample], CpuUse]:
    """The samples between the end of the ramp and the last session start, and the CPU
    used meanwhile."""
    window = [s for s in load_.rec.samples if load_.steady_from <= s.cpu.at <= load_.stopped_at]
    if len(window) < 2:
        window = load_.rec.samples
    return window, CpuUse.between(window[0].cpu, window[-1].cpu)


def whole(load_: Load) -> CpuUse:
    """The CPU used over the whole load phase, drain included."""
    return CpuUse.between(load_.rec.samples[0].cpu, load_.rec.samples[-1].cpu)


def sessions_per_second(load_: Load) -> tuple[float, float]:
    """Completed sessions per second: over the whole phase (drain included), and those
    completed within the steady window per second of it."""
    rec = load_.rec
    rate = rec.sessions_completed / max(load_.ended_at - load_.started_at, 1e-9)
    inside = [t for t in rec.finished_at if load_.steady_from <= t <= load_.stopped_at]
    return rate, len(inside) / max(load_.stopped_at - load_.steady_from, 1e-9)


def streams_held(load_: Load) -> tuple[float, float]:
    """Steady medians of the sessions in flight and of the event streams open."""
    window, _ = steady(load_)
    return (
        percentile([s.sessions for s in window], 50),
        percentile([s.streams for s in window], 50),
    )


@dataclass(frozen=True)
class Budget:
    """Server CPU per session, modelled from the cost of each call alone and the calls a
    quiet session makes, against what a quiet session measured."""

    rows: list[tuple[str, float, float]]  # call, CPU per call (ms), calls per session
    polling_ms: float  # both streams' polls over a quiet session's life
    session_seconds: float  # a quiet session's median duration
    measured_ms: float  # server CPU per quiet session, streams included

    @property
    def modelled_ms(self) -> float:
        return sum(cost * count for _, cost, count in self.rows) + self.polling_ms


def budget(results: Results) -> Budget:
    solo_ = results.solo
    sessions = max(solo_.rec.sessions_completed, 1)
    counts = {
        name: (len(calls.latency_ms) + sum(calls.errors.values())) / sessions
        for name, calls in solo_.rec.calls.items()
    }
    costs = results.costs.cpu_ms
    rows = [(name, costs[name], counts[name]) for name in ENDPOINTS if name in costs]
    rows.append((STREAM, costs.get(STREAM, float("nan")), 2.0))
    # A session's streams stay open as long as it lasts at the load's pace.
    seconds = percentile(results.load.rec.session_seconds or solo_.rec.session_seconds, 50)
    per_stream_second = 0.0
    if results.idle is not None and results.idle.streams:
        per_stream_second = 1000 * results.idle.cpu.server / results.idle.streams
    measured = 1000 * solo_.cpu.server * solo_.cpu.seconds / sessions
    return Budget(rows, 2 * seconds * per_stream_second, seconds, measured)


def targets(results: Results) -> list[str]:
    load_ = results.load
    rec = load_.rec
    held, open_streams = streams_held(load_)
    wanted = STREAMS_HELD * 2 * load_.concurrency
    concurrent = held >= load_.concurrency and open_streams >= wanted
    slow = [
        (name, percentile(rec.calls[name].latency_ms, 99))
        for name in ENDPOINTS
        if name not in EXEMPT and rec.calls[name].latency_ms
    ]
    over = [(name, p99) for name, p99 in slow if not p99 < LATENCY_TARGET_MS]
    worst = max(slow, key=lambda item: item[1]) if slow else ("-", float("nan"))
    incomplete = rec.sessions_started - rec.sessions_completed
    upload = ms(percentile(rec.calls[PHOTO].latency_ms, 99))
    return [
        f"{verdict(concurrent)}: {load_.concurrency} concurrent sessions (steady medians: "
        f"{held:.0f} sessions in flight, {open_streams:.0f} event streams open; at least "
        f"{load_.concurrency} and {wanted:.0f}, {percent(STREAMS_HELD)} of "
        f"{2 * load_.concurrency}, wanted)",
        f"{verdict(rec.errors == 0 and incomplete == 0)}: 0 errors ({rec.http_errors} failed "
        f"calls, {sum(rec.flow_errors.values())} flow errors; {incomplete} of "
        f"{rec.sessions_started} sessions not completed)",
        f"{verdict(not over)}: p99 under {LATENCY_TARGET_MS:g} ms for every call except the "
        "photo upload ("
        + (
            ", ".join(f"`{name}` {ms(p99)} ms" for name, p99 in over)
            if over
            else f"slowest: `{worst[0]}` {ms(worst[1])} ms"
        )
        + f"; photo upload p99 {upload} ms, reported only)",
    ]


def notes(results: Results) -> list[str]:
    """What limited the run, from its own figures."""
    load_ = results.load
    rec = load_.rec
    _, cpu = steady(load_)
    whole_cpu = whole(load_)
    rate, _ = sessions_per_second(load_)
    model = budget(results)
    per_session = model.measured_ms - model.polling_ms  # without the streams' polling
    idle_cores = 0.0
    if results.idle is not None and results.idle.streams:
        idle_cores = results.idle.cpu.server * 2 * load_.concurrency / results.idle.streams
    workers = results.setup.workers
    # Each process runs Python on one core at most (the GIL), and no more than there are.
    cores = min(workers, CORES)
    capacity = 1000 * max(cores - idle_cores, 0.0) / per_session if per_session > 0 else 0.0
    demand = load_.concurrency / model.session_seconds
    loaded_cpu = 1000 * whole_cpu.server * whole_cpu.seconds / max(rec.sessions_completed, 1)
    lines = [
        f"Demand: {load_.concurrency} sessions at once, each {model.session_seconds:.1f} s "
        f"long (the median under load: mostly people's pauses), complete "
        f"{demand:.1f} sessions/s. Supply: a quiet session costs the server "
        f"{model.measured_ms:.0f} ms of CPU ({model.polling_ms:.0f} ms of it its streams' "
        f"polling); {2 * load_.concurrency} open streams cost {idle_cores:.2f} cores by "
        f"themselves (scaled from the idle phase). {workers} server process"
        + ("" if workers == 1 else "es")
        + f" run Python on at most {cores} core"
        + ("" if cores == 1 else "s")
        + " (one each: the GIL), shared with the load generator here, so they can complete "
        f"at most about {capacity:.1f} sessions/s with {2 * load_.concurrency} streams "
        "open: "
        + (
            f"**{demand / capacity:.0f} times less than asked**; the rest waits in queues, "
            "which is the latency above."
            if capacity > 0 and demand > capacity
            else "enough for the demand."
        ),
        "The largest parts of a session's server CPU (the cost table below): "
        + ", ".join(
            f"`{name}` {ms(cost * count)} ms ({count:.0f} x {ms(cost)} ms)"
            for name, cost, count in sorted(
                model.rows, key=lambda row: row[1] * row[2], reverse=True
            )[:3]
        )
        + f"; and the polling of {2 * load_.concurrency} open streams, {idle_cores:.2f} "
        "cores whatever the sessions do.",
        f"Measured under load: {rate:.2f} sessions/s completed, "
        f"{loaded_cpu:.0f} ms of server CPU per completed session (the whole phase, failed "
        f"sessions' work included); server {cpu.server:.2f} cores in the steady window.",
        f"The load generator used {cpu.client:.2f} cores in the steady window; its event "
        f"loop woke sleepers {ms(percentile(rec.loop_lag_ms, 99))} ms late at p99, which "
        "every latency above includes.",
    ]
    others = max(cpu.others, results.solo.cpu.others)
    if others > BUSY_MACHINE_CORES:
        lines.append(
            f"**The machine was not quiet**: programs other than the server and the load "
            f"generator kept up to {others:.2f} cores busy during the run (quiet phase "
            f"{results.solo.cpu.others:.2f}, steady window {cpu.others:.2f}); every time "
            "above is longer for it. Run again on an idle machine to compare."
        )
    pairs = [
        (
            name,
            percentile(rec.calls[name].server_ms, 99),
            percentile(rec.calls[name].latency_ms, 99),
        )
        for name in ENDPOINTS
        if rec.calls[name].latency_ms and rec.calls[name].server_ms
    ]
    if pairs:
        lines.append(
            "p99 Server-Timing / p99 client latency (ms): "
            + ", ".join(f"`{name}` {ms(s)} / {ms(c)}" for name, s, c in pairs)
            + ". The difference is time before the app sees the request (uvicorn's event "
            "loop, shared with the 2N streams and the app's own async code) and in the "
            "load generator."
        )
    return lines
