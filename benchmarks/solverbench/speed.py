"""Speed: ``epipole_from_five`` against OpenCV's 7-point call, and ``solve`` per call in
every case the other sections measure, timed in interleaved timeit rounds in one process."""

from __future__ import annotations

import math
import statistics
import timeit
from collections.abc import Callable
from dataclasses import dataclass

import cv2
from report import markdown_table, verdict

from shared_solver import SolverError, epipole_from_five, solve
from shared_solver.projective import Array
from testbed.phones import PhoneScene, phone_scene
from testbed.scenes import Scene, Taps, facing_scene, tap

from .common import (
    Cameras,
    Given,
    Precisions,
    mixed_taps,
    scene_rng,
    solve_call,
    tap_rng,
)
from .phones import MIXED_SIGMAS, TARGET_SIGMA

FACING_SIGMA = 1.0
ROUND_SECONDS = 0.02
EPIPOLE_SPEED_FACTOR = 1.0
SOLVE_BUDGET_US = 2000.0
SEVEN = "cv2.findFundamentalMat FM_7POINT, 7"
FIVE = "epipole_from_five (cremona, default)"


@dataclass(frozen=True)
class Timing:
    median_us: float
    min_us: float
    calls_per_round: int


@dataclass(frozen=True)
class SolveCase:
    """One timed case of ``solve`` on phone scenes: landmarks, what is given, the cameras."""

    label: str
    landmarks: int
    given: Given
    cameras: Cameras = "unknown"
    mixed: bool = False
    zoom2: float = 1.0


PHONE_CASES = (
    SolveCase("projective 5+e1", 5, "e1"),
    SolveCase("projective 8+e1", 8, "e1"),
    SolveCase("projective 6 + line", 6, "line"),
    SolveCase("projective 7, nothing marked", 7, "none"),
    SolveCase("phone prior 3+e1", 3, "e1", "phone"),
    SolveCase("phone prior 4+e1", 4, "e1", "phone"),
    SolveCase("phone prior 5+e1", 5, "e1", "phone"),
    SolveCase("phone prior 8+e1", 8, "e1", "phone"),
    SolveCase("EXIF focal 3+e1", 3, "e1", "exif"),
    SolveCase("EXIF focal 4+e1", 4, "e1", "exif"),
    SolveCase("EXIF focal 5+e1", 5, "e1", "exif"),
    SolveCase("phone prior 1 + e1 + e2", 1, "both", "phone"),
    SolveCase("phone prior 3 + e1 + e2", 3, "both", "phone"),
    SolveCase("phone prior 6 + line", 6, "line", "phone"),
    SolveCase("phone prior 7, nothing marked", 7, "none", "phone"),
    SolveCase("phone prior 5+e1, mixed precision", 5, "e1", "phone", mixed=True),
    SolveCase("phone prior 5+e1, photo 2 zoomed 2x", 5, "e1", "phone", zoom2=2.0),
)
FACING_LANDMARKS = (5, 6, 8)


def facing_label(n: int) -> str:
    return f"facing: solve {n}+e1 (with uncertainty)"


@dataclass(frozen=True)
class PhoneInput:
    """One phone scene's taps (plain, of mixed precision, zoomed) and the line's angle."""

    scene: PhoneScene
    taps: Taps
    angle: float
    zoomed: PhoneScene
    zoomed_taps: Taps
    mixed: Taps
    precisions: Precisions


def phone_call(case: SolveCase, given: PhoneInput) -> Callable[[], object]:
    scene, taps, precisions, sigma = given.scene, given.taps, None, TARGET_SIGMA
    if case.zoom2 != 1.0:
        scene, taps = given.zoomed, given.zoomed_taps
    if case.mixed:
        taps, precisions, sigma = given.mixed, given.precisions, min(MIXED_SIGMAS)
    return lambda: solve_call(
        scene,
        taps,
        sigma,
        case.landmarks,
        given=case.given,
        line_angle=given.angle,
        cameras=case.cameras,
        precisions=precisions,
    )


def phone_inputs(count: int) -> list[PhoneInput]:
    """The first ``count`` phone scenes (taps at TARGET_SIGMA) that no case refuses."""
    inputs: list[PhoneInput] = []
    for trial in range(count * 5):
        scene = phone_scene(scene_rng("speed phone", trial), 8)
        zoomed = phone_scene(scene_rng("speed phone", trial, 2), 8, zoom2=2.0)
        rng = tap_rng("speed phone", TARGET_SIGMA, trial)
        taps = tap(scene, TARGET_SIGMA, rng)
        zoomed_taps = tap(zoomed, TARGET_SIGMA, rng)
        mixed, precisions = mixed_taps(scene, rng, MIXED_SIGMAS)
        candidate = PhoneInput(
            scene, taps, float(rng.uniform(0, math.pi)), zoomed, zoomed_taps, mixed, precisions
        )
        try:
            for case in PHONE_CASES:
                phone_call(case, candidate)()
        except SolverError:
            continue
        inputs.append(candidate)
        if len(inputs) == count:
            break
    return inputs


FacingInput = tuple[Array, Array, Array, tuple[int, int], tuple[int, int]]


def facing_inputs(count: int) -> list[FacingInput]:
    """(e1 tap, landmarks1, landmarks2, sizes) of noisy facing scenes every timed function
    accepts."""
    inputs = []
    for trial in range(count * 2):
        scene: Scene = facing_scene(scene_rng("speed", trial), 8)
        taps = tap(scene, FACING_SIGMA, tap_rng("speed", FACING_SIGMA, trial))
        try:
            for n in FACING_LANDMARKS:
                solve(
                    taps.landmarks1[:n],
                    taps.landmarks2[:n],
                    epipole1=taps.epipole1,
                    tap_sigma=FACING_SIGMA,
                )
            epipole_from_five(taps.epipole1, taps.landmarks1[:5], taps.landmarks2[:5])
        except SolverError:
            continue
        inputs.append(
            (taps.epipole1, taps.landmarks1, taps.landmarks2, scene.image_size1, scene.image_size2)
        )
        if len(inputs) == count:
            break
    return inputs


def functions(
    facing: list[FacingInput], phones: list[PhoneInput]
) -> dict[str, tuple[Callable[[], object], int]]:
    """Each function runs once over its scenes: (function, calls per run)."""
    five = [(e1, p[:5].copy(), q[:5].copy()) for e1, p, q, _, _ in facing]
    seven = [(p[:7].copy(), q[:7].copy()) for _, p, q, _, _ in facing]

    def facing_solve(n: int) -> Callable[[], object]:
        taps = [(e1, p[:n].copy(), q[:n].copy(), s1, s2) for e1, p, q, s1, s2 in facing]
        return lambda: [
            solve(p, q, epipole1=e1, tap_sigma=FACING_SIGMA, image_size1=s1, image_size2=s2)
            for e1, p, q, s1, s2 in taps
        ]

    def phone_solve(case: SolveCase) -> Callable[[], object]:
        calls = [phone_call(case, given) for given in phones]
        return lambda: [call() for call in calls]

    timed: dict[str, tuple[Callable[[], object], int]] = {
        FIVE: (lambda: [epipole_from_five(*a) for a in five], len(facing)),
        'epipole_from_five (method="linear")': (
            lambda: [epipole_from_five(*a, method="linear") for a in five],
            len(facing),
        ),
        SEVEN: (
            lambda: [cv2.findFundamentalMat(p, q, cv2.FM_7POINT) for p, q in seven],
            len(facing),
        ),
    }
    for n in FACING_LANDMARKS:
        timed[facing_label(n)] = (facing_solve(n), len(facing))
    for case in PHONE_CASES:
        timed[f"phones: solve {case.label}"] = (phone_solve(case), len(phones))
    return timed


@dataclass(frozen=True)
class SpeedResult:
    timings: dict[str, Timing]
    facing_scenes: int
    phone_scenes: int
    rounds: int


def speed(scenes: int, rounds: int) -> SpeedResult:
    """Interleaved rounds: every round times every function once, so drift hits all alike."""
    facing, phones = facing_inputs(scenes), phone_inputs(scenes)
    runs = functions(facing, phones)
    timers = {name: timeit.Timer(function) for name, (function, _) in runs.items()}
    numbers = {}
    for name, timer in timers.items():
        once = timer.timeit(1)  # also a warm-up
        numbers[name] = max(1, math.ceil(ROUND_SECONDS / max(once, 1e-9)))
    per_call: dict[str, list[float]] = {name: [] for name in timers}
    for _ in range(rounds):
        for name, timer in timers.items():
            elapsed = timer.timeit(numbers[name])
            per_call[name].append(elapsed / (numbers[name] * runs[name][1]) * 1e6)
    return SpeedResult(
        {
            name: Timing(statistics.median(times), min(times), numbers[name] * runs[name][1])
            for name, times in per_call.items()
        },
        len(facing),
        len(phones),
        rounds,
    )


def speed_targets(timings: dict[str, Timing]) -> list[tuple[bool, str]]:
    seven = timings[SEVEN].median_us
    five = timings[FIVE].median_us
    passed = five <= EPIPOLE_SPEED_FACTOR * seven
    lines = [
        (
            passed,
            f"{verdict(passed)}: epipole_from_five no slower than OpenCV's 7-point call "
            f"(ratio <= {EPIPOLE_SPEED_FACTOR:g}; median {five:.1f} us vs {seven:.1f} us, "
            f"{five / seven:.2f}x)",
        )
    ]
    for n in FACING_LANDMARKS:
        spent = timings[facing_label(n)].median_us
        passed = spent < SOLVE_BUDGET_US
        lines.append(
            (
                passed,
                f"{verdict(passed)}: facing scenes, solve with uncertainty, {n} landmarks + e1, "
                f"under {SOLVE_BUDGET_US / 1000:g} ms (median {spent / 1000:.2f} ms)",
            )
        )
    phone = {name: t.median_us for name, t in timings.items() if name.startswith("phones: solve ")}
    slowest = max(phone, key=lambda name: phone[name])
    over = [name for name, spent in phone.items() if spent > SOLVE_BUDGET_US]
    passed = not over
    lines.append(
        (
            passed,
            f"{verdict(passed)}: phone scenes at {TARGET_SIGMA:g} px, solve median <= "
            f"{SOLVE_BUDGET_US / 1000:g} ms in every one of the {len(phone)} cases, camera-aware "
            f"ones included (slowest: {slowest.removeprefix('phones: solve ')} "
            f"{phone[slowest] / 1000:.2f} ms; over budget: "
            + (
                ", ".join(
                    f"{name.removeprefix('phones: solve ')} {phone[name] / 1000:.2f} ms"
                    for name in over
                )
                or "none"
            )
            + ")",
        )
    )
    return lines


def speed_table(timings: dict[str, Timing]) -> str:
    seven = timings[SEVEN].median_us
    return markdown_table(
        [
            "function",
            "median (us/call)",
            "min (us/call)",
            "median / OpenCV 7-point",
            "calls per round",
        ],
        [
            [
                name,
                f"{t.median_us:.1f}",
                f"{t.min_us:.1f}",
                f"{t.median_us / seven:.2f}x",
                str(t.calls_per_round),
            ]
            for name, t in timings.items()
        ],
    )
