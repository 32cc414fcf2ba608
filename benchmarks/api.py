"""Buddy Search API benchmark: solve throughput, 12 MP upload and overlay render, in one run.

Everything runs against one real uvicorn process (``backend.main:app``, one worker, SQLite
in a temporary folder) that this script starts on a free loopback port and stops at the end:

1. ``POST /api/solve`` (8 landmarks + the tap e1 on friend 2 of a ``facing_scene``, 1 px
   tap noise) against ``GET /api/version`` (no database: the cheapest endpoint), from the
   load generator of the load benchmark, Locust (one keep-alive connection per worker, a
   greenlet each, in this process) in interleaved
   rounds, so both endpoints see the same machine state; 8 workers, then 1 (no queueing).
   Per endpoint: requests/s, client latency, the server's own time (the ``Server-Timing``
   header) and the CPU time the server process and the load generator spent per request
   (``/proc``), because both share the same 2 cores; and ``shared_solver.solve`` alone on
   the same request, in this process, for what the HTTP layer adds.
2. ``PUT /api/sessions/{id}/photo`` of a photo-like 4032x3024 JPEG (a temple photo upscaled,
   with sensor-like noise), repeated: the server time to accept and store it.
3. ``GET /api/sessions/{id}/overlay/joiner`` of the stored 2560x1920 photo: JPEG renders
   (each after a 0.5 px change of one tap, which makes a new answer version; overlays are
   drawn for each request, never kept) and PNG renders.

Run from the repository root:

    .venv/bin/python benchmarks/api.py [--seconds S] [--out PATH]     (``make bench-api``)

The report is printed and written as Markdown to ``docs/api-benchmark.md``.
"""

from __future__ import annotations

import json
import platform
import sqlite3
import tempfile
import time
from collections.abc import Callable, Sequence
from contextlib import closing
from dataclasses import dataclass, field, fields
from importlib.metadata import version
from pathlib import Path
from typing import Any, ClassVar

import locust.env  # first of the third-party imports: Locust patches the standard library

# isort: split
import cv2
import gevent
import httpx2
import numpy as np
import psutil
from locust import FastHttpUser, constant, task
from report import (
    ROOT,
    command_line,
    cpu_snapshot,
    heading,
    log,
    machine,
    markdown_table,
    ms,
    percent,
    percentile,
    publish,
    quantiles,
    server_timing_ms,
    source_state,
    targets_section,
    timed,
    uvicorn_stack,
)

from backend.settings import Settings
from deploy.replica import Server, serve
from shared_solver import solve
from testbed.client import Phone, numbered, start
from testbed.scenes import facing_scene, tap

DEFAULT_OUT = ROOT / "docs" / "api-benchmark.md"
TEMPLE = ROOT / "tests" / "data" / "temple"

# --- what is measured, and the targets ---------------------------------------------------

DEFAULT_SECONDS = 10.0
WARMUP_SECONDS = 2.0
ROUNDS = 5  # each endpoint's load time is split into this many interleaved slices
CONCURRENCY = 8
SEQUENTIAL_SLICE_SECONDS = 0.2  # one worker, for the server's time without queueing
IN_PROCESS_SOLVES = 300
SOLVE_THROUGHPUT_TARGET = 0.6  # /api/solve requests/s at least this share of /api/version's

VERSION = "GET /api/version"
SOLVE = "POST /api/solve"

SEED = 20240601
SOLVE_SCENE_SEED = (SEED, 21)
SESSION_SCENE_SEED = (SEED, 22)
PHOTO_NOISE_SEED = (SEED, 23)
SOLVE_LANDMARKS = 8
SOLVE_SIGMA = 1.0

UPLOAD_SIZE = (4032, 3024)  # 12 MP, a phone camera's default
UPLOAD_QUALITY = 92
UPLOAD_NOISE_SIGMA = 6.0  # grey levels: the sensor noise of a phone photo indoors
UPLOADS = 15
UPLOAD_BUDGET_MS = 300.0

SESSION_FOCAL = 2200.0
RENDERS = 15
PNG_RENDERS = 5
TAP_NUDGE_PX = 0.5
RENDER_BUDGET_MS = 50.0

DATABASE_NAME = "bench.db"


# --- the server ------------------------------------------------------------------------------


def database_url(folder: Path) -> str:
    return f"sqlite:///{folder / DATABASE_NAME}"


def journal_mode(folder: Path) -> str:
    """The journal mode the app left in the database file (WAL persists in the file)."""
    with closing(sqlite3.connect(folder / DATABASE_NAME)) as database:
        return str(database.execute("PRAGMA journal_mode").fetchone()[0])


# --- 1. /api/solve against /api/version under load ------------------------------------------


@dataclass(frozen=True)
class Sample:
    latency_ms: float  # client: request sent to response read
    server_ms: float  # Server-Timing


@dataclass
class Load:
    """Everything measured for one endpoint, summed over its slices."""

    samples: list[Sample] = field(default_factory=list)
    errors: int = 0
    seconds: float = 0.0
    server_cpu: float = 0.0
    client_cpu: float = 0.0
    machine_busy: float = 0.0
    machine_total: float = 0.0

    @property
    def requests(self) -> int:
        return len(self.samples)

    @property
    def per_second(self) -> float:
        return self.requests / self.seconds

    def server_time(self, q: float) -> float:
        return percentile([s.server_ms for s in self.samples], q)

    def cpu_ms_per_request(self, seconds: float) -> float:
        return 1000 * seconds / self.requests

    def cores(self, seconds: float) -> float:
        """CPU seconds per wall second: 1.0 is one core kept busy."""
        return seconds / self.seconds


@dataclass(frozen=True)
class Call:
    """One endpoint's request; the solve request's JSON is encoded once, outside the timing."""

    method: str
    path: str
    body: str | None = None


class Worker(FastHttpUser):
    """One worker of the load generator (Locust, as the load benchmark): requests of
    ``call`` back to back on its own keep-alive connection."""

    wait_time = constant(0)
    call: ClassVar[Call]

    @task
    def send(self) -> None:
        headers = {"Content-Type": "application/json"} if self.call.body else {}
        self.client.request(self.call.method, self.call.path, data=self.call.body, headers=headers)


class Workers:
    """Locust's workers in this process, started on one endpoint for each slice; each
    answer kept as a :class:`Sample` (an error when not 200)."""

    def __init__(self, server: Server) -> None:
        self.server = server
        self.environment = locust.env.Environment(user_classes=[Worker], host=server.base_url)
        self.runner = self.environment.create_local_runner()
        self.samples: list[Sample] = []
        self.errors = 0
        self.environment.events.request.add_listener(self._heard)  # type: ignore[no-untyped-call]

    def _heard(self, response_time: float, response: Any, exception: Any, **_: Any) -> None:
        if exception is None and response.status_code == 200:
            self.samples.append(Sample(response_time, server_timing_ms(response)))
        else:
            self.errors += 1

    def load_slice(self, call: Call, workers: int, s: float) -> Load:
        """``workers`` on one endpoint for ``s`` seconds (once all have started); the CPU
        spent meanwhile."""
        Worker.call = call
        self.runner.start(workers, spawn_rate=workers * 1000)
        while self.runner.user_count < workers:
            gevent.sleep(0.001)
        self.samples, self.errors = [], 0
        before = cpu_snapshot([self.server.pid])
        started = time.perf_counter()
        gevent.sleep(s)
        elapsed = time.perf_counter() - started
        after = cpu_snapshot([self.server.pid])
        samples, errors = self.samples, self.errors
        self.runner.stop()
        return Load(
            samples=samples,
            errors=errors,
            seconds=elapsed,
            server_cpu=after.server - before.server,
            client_cpu=after.client - before.client,
            machine_busy=after.machine_busy - before.machine_busy,
            machine_total=after.machine_total - before.machine_total,
        )

    def interleaved(self, calls: dict[str, Call], workers: int, s: float) -> dict[str, Load]:
        """``ROUNDS`` rounds; each gives each endpoint one slice, the order alternating
        between rounds, so slow drift of the machine hits both endpoints alike."""
        loads = {name: Load() for name in calls}
        for round_ in range(ROUNDS):
            order = list(calls) if round_ % 2 == 0 else list(reversed(calls))
            for name in order:
                add(loads[name], self.load_slice(calls[name], workers, s))
        return loads


def add(total: Load, part: Load) -> None:
    """``part``'s samples and sums added to ``total``'s, field by field."""
    for name in (f.name for f in fields(Load)):
        setattr(total, name, getattr(total, name) + getattr(part, name))


def solve_request() -> dict[str, Any]:
    """8 landmarks + e1 of a facing scene (1600x1200), 1 px tap noise, as /api/solve takes it."""
    rng = np.random.default_rng(SOLVE_SCENE_SEED)
    scene = facing_scene(rng, SOLVE_LANDMARKS)
    taps = tap(scene, SOLVE_SIGMA, rng)
    return {
        "points1": taps.landmarks1.round(2).tolist(),
        "points2": taps.landmarks2.round(2).tolist(),
        "epipole1": taps.epipole1.round(2).tolist(),
        "tap_sigma": SOLVE_SIGMA,
        "image_size1": list(scene.image_size1),
        "image_size2": list(scene.image_size2),
    }


@dataclass(frozen=True)
class Throughput:
    loaded: dict[str, Load]  # CONCURRENCY workers
    sequential: dict[str, Load]  # one worker: the server's time without queueing
    solve_method: str
    slice_seconds: float
    solve_in_process_ms: float  # shared_solver.solve alone, in this process


def solve_in_process_ms(request: dict[str, Any]) -> float:
    """Median wall time of ``shared_solver.solve`` on ``request`` in this process, ms: the
    part of the endpoint's cost that is the solver itself."""
    arguments = {k: v for k, v in request.items() if k not in ("points1", "points2")}
    points = (request["points1"], request["points2"])
    times = []
    for _ in range(IN_PROCESS_SOLVES):
        started = time.perf_counter()
        solve(*points, **arguments)
        times.append((time.perf_counter() - started) * 1000)
    return percentile(times, 50)


def throughput(server: Server, seconds: float) -> Throughput:
    """A warm-up of each endpoint, interleaved rounds with ``CONCURRENCY`` workers, then
    shorter interleaved rounds with one worker."""
    request = solve_request()
    calls = {
        VERSION: Call("GET", "/api/version"),
        SOLVE: Call("POST", "/api/solve", json.dumps(request)),
    }
    slice_seconds = seconds / ROUNDS
    answer = httpx2.post(f"{server.base_url}/api/solve", json=request, timeout=30)
    answer.raise_for_status()
    workers = Workers(server)
    try:
        for call in calls.values():
            workers.load_slice(call, CONCURRENCY, WARMUP_SECONDS)
        loaded = workers.interleaved(calls, CONCURRENCY, slice_seconds)
        sequential = workers.interleaved(calls, 1, SEQUENTIAL_SLICE_SECONDS)
    finally:
        workers.runner.quit()
    return Throughput(
        loaded,
        sequential,
        str(answer.json()["method"]),
        slice_seconds,
        solve_in_process_ms(request),
    )


# --- 2 and 3. a session: 12 MP uploads, overlay renders ---------------------------------------


def photo_like_jpeg(name: str, rng: np.random.Generator) -> bytes:
    """A temple photo upscaled to 12 MP (bicubic) with Gaussian sensor-like noise, as a
    phone's JPEG: real edges and texture, not a flat or pure-noise image."""
    image = cv2.imread(str(TEMPLE / f"{name}.png"), cv2.IMREAD_COLOR)
    if image is None:
        raise FileNotFoundError(TEMPLE / f"{name}.png")
    large = cv2.resize(image, UPLOAD_SIZE, interpolation=cv2.INTER_CUBIC).astype(np.float32)
    large += np.asarray(rng.normal(0.0, UPLOAD_NOISE_SIGMA, large.shape), dtype=np.float32)
    pixels = np.clip(np.rint(large), 0, 255).astype(np.uint8)
    ok, encoded = cv2.imencode(".jpg", pixels, [cv2.IMWRITE_JPEG_QUALITY, UPLOAD_QUALITY])
    if not ok:
        raise RuntimeError("OpenCV could not encode the upload")
    return bytes(encoded.tobytes())


def measured(
    call: Callable[..., httpx2.Response], *args: Any, **kwargs: Any
) -> tuple[httpx2.Response, Sample]:
    """A phone's call (:class:`testbed.client.Phone`'s ``call(*args, **kwargs)``), timed;
    fails on an error."""
    started = time.perf_counter()
    response = call(*args, **kwargs)
    elapsed = (time.perf_counter() - started) * 1000
    if not response.is_success:
        request = response.request
        raise RuntimeError(f"{request.method} {request.url.path}: {response.text[:300]}")
    return response, Sample(elapsed, server_timing_ms(response))


@dataclass(frozen=True)
class Uploads:
    upload_bytes: int
    stored: dict[str, Any]
    samples: list[Sample]


def uploads(starter: Phone, photo: bytes) -> Uploads:
    """The starter's photo, uploaded ``UPLOADS`` times (each replaces the one before)."""
    samples = []
    stored: dict[str, Any] = {}
    for _ in range(UPLOADS):
        response, sample = measured(starter.upload, photo)
        stored = response.json()
        samples.append(sample)
    return Uploads(len(photo), stored, samples)


@dataclass(frozen=True)
class Renders:
    jpeg: list[Sample]
    png: list[Sample]
    taps: list[Sample]  # PUT taps of the nudges: solve + state (informative)
    method: str
    jpeg_bytes: int
    png_bytes: int


def landmark_taps(points: np.ndarray, size: tuple[int, int]) -> list[dict[str, float]]:
    """Landmarks #1..#n at ``points``, kept on the photo."""
    return numbered(np.clip(points, 0, size))


def decoded_overlay(data: bytes, size: tuple[int, int]) -> None:
    """Fails unless ``data`` decodes to a (height, width, 3) picture."""
    image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
    expected = (size[1], size[0], 3)
    if image is None or image.shape != expected:
        shape = None if image is None else image.shape
        raise RuntimeError(f"the overlay decodes to {shape}, not {expected}")


def tap_both(
    starter: Phone, joiner: Phone, size: tuple[int, int]
) -> tuple[dict[str, Any], list[dict[str, float]]]:
    """Both phones tap 8 landmarks of a facing scene of the stored size, the starter also
    their friend (1 px tap noise); the state with its answer, and the joiner's landmarks."""
    rng = np.random.default_rng(SESSION_SCENE_SEED)
    scene = facing_scene(rng, SOLVE_LANDMARKS, image_size=size, focal=SESSION_FOCAL)
    noisy = tap(scene, SOLVE_SIGMA, rng)
    friend = noisy.epipole1.clip(0, size).tolist()
    starter.tapped(landmarks=landmark_taps(noisy.landmarks1, size), friend=friend)
    joiner_landmarks = landmark_taps(noisy.landmarks2, size)
    state = joiner.tapped(landmarks=joiner_landmarks)
    if state.get("answer") is None:
        raise RuntimeError(f"no answer from the session's taps: {state.get('answer_error')}")
    return state, joiner_landmarks


def renders(starter: Phone, joiner: Phone, size: tuple[int, int]) -> Renders:
    """Renders of the joiner's overlay, each after a new answer version (the joiner's
    landmark #1 moved by 0.5 px)."""
    state, landmarks = tap_both(starter, joiner, size)
    method = str(state["answer"]["method"])
    drawn: dict[str, list[Sample]] = {"jpeg": [], "png": [], "taps": []}
    sizes = {"jpeg": 0, "png": 0}
    for render in range(RENDERS + PNG_RENDERS):
        nudge = TAP_NUDGE_PX if render % 2 == 0 else -TAP_NUDGE_PX
        landmarks[0]["x"] = float(np.clip(landmarks[0]["x"] + nudge, 0, size[0]))
        before = state["answer_version"]
        response, sample = measured(joiner.tap, landmarks=landmarks)
        state = response.json()
        drawn["taps"].append(sample)
        if state.get("answer") is None or state["answer_version"] == before:
            raise RuntimeError(f"the move made no new answer: {state.get('answer_error')}")
        fmt = "jpeg" if render < RENDERS else "png"
        first, sample = measured(joiner.call, "GET", "/overlay/joiner", params={"format": fmt})
        decoded_overlay(first.content, size)
        sizes[fmt] = len(first.content)
        drawn[fmt].append(sample)
    return Renders(drawn["jpeg"], drawn["png"], drawn["taps"], method, *sizes.values())


@dataclass(frozen=True)
class SessionFigures:
    uploads: Uploads
    renders: Renders


def session(server: Server) -> SessionFigures:
    """One two-phone session: the starter's uploads, then the joiner, taps and overlays."""
    rng = np.random.default_rng(PHOTO_NOISE_SEED)
    starter_photo = photo_like_jpeg("templeSR0006", rng)
    joiner_photo = photo_like_jpeg("templeSR0003", rng)
    with httpx2.Client(base_url=server.base_url, timeout=60) as http:
        starter, code = start(http)
        uploaded = uploads(starter, starter_photo)
        joined = http.post("/api/sessions/join", json={"code": code})
        joined.raise_for_status()
        joiner = Phone(http, starter.session_id, joined.json()["token"], "joiner")
        stored = joiner.uploaded(joiner_photo)
        size = (int(stored["width"]), int(stored["height"]))
        drawn = renders(starter, joiner, size)
        starter.ok("DELETE", expect=204)
    return SessionFigures(uploaded, drawn)


# --- the report ----------------------------------------------------------------------------


# The throughput table's columns after the endpoint and its workers: each one's header and
# its cell for one endpoint's load.
LOAD_COLUMNS: dict[str, Callable[[Load], str]] = {
    "requests": lambda load: str(load.requests),
    "requests/s": lambda load: f"{load.per_second:.0f}",
    "client p50 / p99 (ms)": lambda load: quantiles([s.latency_ms for s in load.samples], (50, 99)),
    "Server-Timing p50 / p99 (ms)": lambda load: quantiles(
        [s.server_ms for s in load.samples], (50, 99)
    ),
    "server CPU per request (ms)": lambda load: f"{load.cpu_ms_per_request(load.server_cpu):.3f}",
    "load generator CPU per request (ms)": (
        lambda load: f"{load.cpu_ms_per_request(load.client_cpu):.3f}"
    ),
    "server process busy (cores)": lambda load: f"{load.cores(load.server_cpu):.2f}",
    "load generator busy (cores)": lambda load: f"{load.cores(load.client_cpu):.2f}",
    "machine busy (of 2 cores)": lambda load: percent(load.machine_busy / load.machine_total),
    "errors": lambda load: str(load.errors),
}


def throughput_table(result: Throughput) -> str:
    loads = [
        *((name, CONCURRENCY, load) for name, load in result.loaded.items()),
        *((name, 1, load) for name, load in result.sequential.items()),
    ]
    return markdown_table(
        ["endpoint", "workers", *LOAD_COLUMNS],
        [
            [f"`{name}`", str(workers), *(cell(load) for cell in LOAD_COLUMNS.values())]
            for name, workers, load in loads
        ],
    )


def throughput_target(result: Throughput) -> tuple[str, bool]:
    version_load = result.loaded[VERSION]
    solve_load = result.loaded[SOLVE]
    ratio = solve_load.per_second / version_load.per_second
    errors = solve_load.errors + version_load.errors
    return (
        f"`/api/solve` reaches at least {percent(SOLVE_THROUGHPUT_TARGET)} of "
        f"`/api/version`'s throughput in the same run, {CONCURRENCY} workers "
        f"({solve_load.per_second:.0f} vs {version_load.per_second:.0f} requests/s, "
        f"{percent(ratio)}; errors: {errors})",
        ratio >= SOLVE_THROUGHPUT_TARGET and errors == 0,
    )


def throughput_notes(result: Throughput) -> list[str]:
    """What limited each endpoint, from this run's figures."""
    version_load, solve_load = result.loaded[VERSION], result.loaded[SOLVE]
    version_cpu = version_load.cpu_ms_per_request(version_load.server_cpu)
    solve_cpu = solve_load.cpu_ms_per_request(solve_load.server_cpu)
    # One process runs Python on one core at a time (the GIL): at most 1000 / cpu_ms per s.
    allowed_ms = 1000 / (SOLVE_THROUGHPUT_TARGET * version_load.per_second)
    solver_ms = result.solve_in_process_ms
    sequential = result.sequential
    return [
        f"With {CONCURRENCY} workers, `/api/version` kept the server process "
        f"{version_load.cores(version_load.server_cpu):.2f} cores busy and the load generator "
        f"{version_load.cores(version_load.client_cpu):.2f} "
        f"({percent(version_load.machine_busy / version_load.machine_total)} of the machine); "
        f"`/api/solve` kept the server {solve_load.cores(solve_load.server_cpu):.2f} cores "
        f"busy and the load generator {solve_load.cores(solve_load.client_cpu):.2f}.",
        f"Server CPU per request: {solve_cpu:.3f} ms for `/api/solve`, {version_cpu:.3f} ms for "
        f"`/api/version`; if only the server's CPU limited both, on one core's worth of "
        f"Python (the GIL), the ratio of their rates would be {percent(version_cpu / solve_cpu)}.",
        f"For `/api/solve` to reach {percent(SOLVE_THROUGHPUT_TARGET)} of the "
        f"{version_load.per_second:.0f} requests/s measured for `/api/version`, the server "
        f"could spend at most {allowed_ms:.2f} ms of CPU per solve request; "
        f"`shared_solver.solve` alone takes {solver_ms:.2f} ms on this request "
        f"(median of {IN_PROCESS_SOLVES} calls in the benchmark's process, same run)"
        + (
            ": at this rate one server process cannot meet the target, and a load generator "
            "that left the server more of the machine would only raise that rate."
            if solver_ms > allowed_ms
            else "."
        ),
        f"With one worker (no queueing), Server-Timing p50 is "
        f"{ms(sequential[SOLVE].server_time(50))} ms for `/api/solve` and "
        f"{ms(sequential[VERSION].server_time(50))} ms for `/api/version`; with "
        f"{CONCURRENCY} workers it also holds the wait for the GIL and a worker thread.",
    ]


def summary_row(name: str, samples: Sequence[Sample]) -> list[str]:
    """Median / p90 / max of the server's times and the client's."""
    server = quantiles([s.server_ms for s in samples], (50, 90, 100))
    return [
        name,
        str(len(samples)),
        server,
        quantiles([s.latency_ms for s in samples], (50, 90, 100)),
    ]


def session_table(figures: SessionFigures) -> str:
    drawn = figures.renders
    return markdown_table(
        ["request", "n", "server time median / p90 / max (ms)", "client median / p90 / max (ms)"],
        [
            summary_row("`PUT /photo`, 12 MP JPEG (starter, replacing)", figures.uploads.samples),
            summary_row("`GET /overlay/joiner`, jpeg (render)", drawn.jpeg),
            summary_row("`GET /overlay/joiner?format=png` (informative)", drawn.png),
            summary_row("`PUT /taps` before each render: solve + state (informative)", drawn.taps),
        ],
    )


def session_targets(figures: SessionFigures) -> list[tuple[str, bool]]:
    upload = percentile([s.server_ms for s in figures.uploads.samples], 50)
    render = percentile([s.server_ms for s in figures.renders.jpeg], 50)
    return [
        (
            f"a 12 MP JPEG accepted and stored in at most "
            f"{UPLOAD_BUDGET_MS:g} ms of server time (median {ms(upload)} ms)",
            upload <= UPLOAD_BUDGET_MS,
        ),
        (
            f"a jpeg overlay of the stored 2560 px photo rendered in at most "
            f"{RENDER_BUDGET_MS:g} ms of server time (median {ms(render)} ms)",
            render <= RENDER_BUDGET_MS,
        ),
    ]


def filesystem_type(path: Path) -> str:
    """The type of the file system holding ``path`` (its longest mount point)."""
    holding = [
        part
        for part in psutil.disk_partitions(all=True)
        if str(path).startswith(part.mountpoint.rstrip("/") + "/") or str(path) == part.mountpoint
    ]
    # The last mounted of the longest: one mounted over another hides it.
    deepest = max(reversed(holding), key=lambda part: len(part.mountpoint), default=None)
    return deepest.fstype if deepest else "unknown"


def header(settings: Settings, database: str) -> str:
    versions = ", ".join(
        f"{name} {version(name)}"
        for name in ("uvicorn", "fastapi", "starlette", "h11", "httpx2", "numpy", "pillow")
    )
    code = source_state("backend", "shared_solver")
    return "\n".join(
        [
            *heading("API benchmark", "benchmarks/api.py", "bench-api"),
            machine(
                ". **The load generator runs on the same machine as the server**: both share "
                "these cores."
            ),
            f"- Python {platform.python_version()}, {versions}, OpenCV {cv2.__version__}",
            f"- Code under test (backend, shared_solver): {code}",
            "- Server: `python -m uvicorn backend.main:app --host 127.0.0.1 --port <free> "
            f"--no-access-log`, one worker process, {uvicorn_stack()}; loopback only.",
            f"- Settings: SQLite in a new temporary folder ({database}; the app sets "
            f"synchronous=FULL); stored_photo_side = {settings.stored_photo_side}, "
            f"max_body_bytes = {settings.max_body_bytes}, "
            f"max_photo_pixels = {settings.max_photo_pixels}, session tap_sigma = "
            f"{settings.tap_sigma:g}; the rest default.",
            "- Server time is the `app` part of the `Server-Timing` header"
            " (`app;dur=<ms>, db;dur=<ms>`): from the request's arrival at the app to the"
            " start of its response, body upload included.",
        ]
    )


def throughput_section(result: Throughput, seconds: float) -> list[str]:
    return [
        "## 1. `/api/solve` against `/api/version`, under load",
        f"Load generator: Locust {version('locust')} in this Python process, {CONCURRENCY} "
        "workers (FastHttpUser greenlets), each with its own keep-alive connection, sending "
        "requests back to back, **on the same "
        f"2-core machine as the server**. After a {WARMUP_SECONDS:g} s warm-up of each "
        f"endpoint, {ROUNDS} interleaved rounds (order alternating) of "
        f"{result.slice_seconds:g} s per endpoint: {seconds:g} s each. Then {ROUNDS} shorter "
        f"interleaved rounds ({SEQUENTIAL_SLICE_SECONDS:g} s) with one worker, for the "
        f"server's time without queueing. `/api/solve` gets {SOLVE_LANDMARKS} landmarks + e1 "
        f"of a `facing_scene` (1600x1200) with {SOLVE_SIGMA:g} px tap noise, tap_sigma "
        f"{SOLVE_SIGMA:g}, both image sizes (answered by `{result.solve_method}`). CPU from "
        "/proc over the same slices: the server process's utime + stime (all its threads), "
        "this process's CPU time, and the machine's busy time over all cores.",
        throughput_table(result),
        "\n".join(f"- {line}" for line in throughput_notes(result)),
        "What limits the numbers: one Python process runs Python on about "
        "one core at a time (the GIL), and the load generator and the server share 2 cores. "
        "A side near 1.00 cores is saturated; when the machine is near 100 %, the two sides "
        "slow each other. Where the load generator's CPU per request is close to the "
        "server's (the table), the rate is as much the client's limit as the server's; the "
        "server CPU per request is the cleaner comparison of what each endpoint costs.",
    ]


def session_section(figures: SessionFigures) -> list[str]:
    stored = figures.uploads.stored
    drawn = figures.renders
    return [
        "## 2 and 3. A session: 12 MP uploads, overlay renders",
        f"One session, one request at a time. Upload: `templeSR0006.png` upscaled to "
        f"{UPLOAD_SIZE[0]}x{UPLOAD_SIZE[1]} (bicubic) with Gaussian noise sigma "
        f"{UPLOAD_NOISE_SIGMA:g}, JPEG quality {UPLOAD_QUALITY} "
        f"({figures.uploads.upload_bytes / 1e6:.2f} MB, multipart), put {UPLOADS} times as the "
        f"starter's photo (each replaces the last); stored as {stored['width']}x"
        f"{stored['height']} (scale {stored['scale']:.4f}). Then the joiner joins with the code "
        "from the starter's state and uploads `templeSR0003` made the same way; both tap "
        f"{SOLVE_LANDMARKS} landmarks (the starter also their friend, e1) from a `facing_scene` "
        "of the stored "
        f"size (f = {SESSION_FOCAL:g} px, {SOLVE_SIGMA:g} px tap noise), answered by "
        f"`{drawn.method}`. Each render follows a `PUT /taps` that moves the joiner's landmark "
        f"#1 by {TAP_NUDGE_PX:g} px (a new answer version). Every overlay decodes to "
        f"{stored['height']}x{stored['width']}x3; jpeg {drawn.jpeg_bytes / 1e6:.2f} MB, png "
        f"{drawn.png_bytes / 1e6:.2f} MB.",
        session_table(figures),
    ]


@dataclass(frozen=True)
class Results:
    settings: Settings
    database: str  # as found after the run: journal mode, file system
    seconds: float
    throughput: Throughput
    session: SessionFigures
    timings: dict[str, float]


def report(results: Results) -> str:
    targets = [throughput_target(results.throughput), *session_targets(results.session)]
    spent = ", ".join(f"{name} {s:.1f} s" for name, s in results.timings.items())
    sections = [
        header(results.settings, results.database),
        *throughput_section(results.throughput, results.seconds),
        *session_section(results.session),
        "\n".join(targets_section(targets)),
        f"Wall time: {sum(results.timings.values()):.1f} s ({spent}; interpreter start-up "
        "and imports not included).",
    ]
    return "\n\n".join(sections) + "\n"


# --- running it ----------------------------------------------------------------------------


def run(seconds: float) -> Results:
    timings: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="buddy-bench-") as temporary:
        folder = Path(temporary)
        settings = Settings(_env_file=ROOT / ".env", database_url=database_url(folder))
        log("[server start] ...")
        starting = time.perf_counter()
        with serve(folder, env={"BUDDY_DATABASE_URL": database_url(folder)}) as server:
            timings["server start"] = time.perf_counter() - starting
            loads = timed(timings, "throughput", lambda: throughput(server, seconds))
            figures = timed(timings, "session", lambda: session(server))
        database = f"journal mode {journal_mode(folder)}, on {filesystem_type(folder)}"
        return Results(settings, database, seconds, loads, figures, timings)


def main(argv: Sequence[str] | None = None) -> None:
    parser = command_line(__doc__, DEFAULT_OUT)
    parser.add_argument(
        "--seconds", type=float, default=DEFAULT_SECONDS, help="load s per endpoint after warm-up"
    )
    args = parser.parse_args(argv)
    if not 0 < args.seconds <= 120:
        parser.error("--seconds must be in (0, 120]")
    publish(report(run(args.seconds)), args.out)


if __name__ == "__main__":
    main()
