"""Phone scenes (:func:`testbed.phones.phone_scene`): the projective and the camera-aware
routes against OpenCV, zoomed photos without EXIF, and the coverage of the camera-aware
route case by case."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Literal

import cv2
import numpy as np
from report import markdown_table, verdict

from shared_solver.minimal.epipole_and_three import rotations_from_three
from shared_solver.projective import Array
from testbed.phones import PhoneScene, phone_scene, zoom_from_prior
from testbed.scenes import Taps, tap

from .common import (
    Cameras,
    Given,
    Outcome,
    Precisions,
    Row,
    Summary,
    Target,
    cases_table,
    coverage_cell,
    errors_cell,
    failures,
    fell_back,
    fmt,
    interval,
    mixed_taps,
    ours,
    pixel_error,
    scene_rng,
    summaries,
    tap_rng,
)
from .facing import opencv

PHONE_SIGMAS = (1.0, 3.0, 8.0)
TARGET_SIGMA = 3.0
ZOOMS = (2.0, 3.0)
MIXED_SIGMAS = (2.0, 10.0)  # each tap at one of these, px, at even odds
SCENE_LANDMARKS = 8
# OpenCV's RANSAC keeps a tap as an inlier within this many tap sigmas of its epipolar line.
RANSAC_SIGMAS = 3.0

PhoneMethod = Callable[[PhoneScene, Taps, float], Outcome]


def phone_trial(stream: str, sigma: float, trial: int) -> tuple[PhoneScene, Taps, float]:
    """Scene, taps at ``sigma`` and the direction of a line through the e1 tap, of one trial.

    ``stream`` is ``phone`` (main cameras), ``zoom2``/``zoom3`` (photo 2 zoomed) or
    ``prior`` (both photos zoomed by factors drawn from the phone prior); the scene of trial
    i is the same at every sigma.
    """
    rng = scene_rng(stream, trial)
    if stream == "prior":
        zoom1, zoom2 = zoom_from_prior(rng), zoom_from_prior(rng)
    else:
        zoom1, zoom2 = 1.0, {"phone": 1.0, "zoom2": 2.0, "zoom3": 3.0}[stream]
    scene = phone_scene(rng, SCENE_LANDMARKS, zoom1=zoom1, zoom2=zoom2)
    rng = tap_rng(stream, sigma, trial)
    taps = tap(scene, sigma, rng)
    return scene, taps, float(rng.uniform(0.0, math.pi))


def draws(stream: str, sigma: float, trials: int) -> Iterator[tuple[PhoneScene, Taps, float]]:
    """The scenes and taps of :func:`phone_trial`'s first ``trials`` trials, and ``sigma``."""
    for trial in range(trials):
        scene, taps, _ = phone_trial(stream, sigma, trial)
        yield scene, taps, sigma


def normalised(intrinsics: Array, pixels: Array) -> Array:
    """(N, 2) pixels -> (N, 2) normalised image coordinates K^-1 x."""
    rays = np.column_stack([pixels, np.ones(len(pixels))]) @ np.linalg.inv(intrinsics).T
    return rays[:, :2] / rays[:, 2:]


def opencv_essential(scene: PhoneScene, taps: Taps, sigma: float, landmarks: int) -> Outcome:
    """``cv2.findEssentialMat`` with the true intrinsics on the first ``landmarks`` taps, no e1.

    Points are normalised with each camera's K, then passed with focal 1 and principal point
    (0, 0). RANSAC keeps taps within ``RANSAC_SIGMAS`` sigmas (in normalised units, the mean
    focal length); on 5 landmarks it returns every root of the 5-point solver, stacked, and
    the error is that of the root whose e2 = K2 (left null vector of E) is nearest the truth
    (an oracle no real caller has, so this flatters OpenCV).
    """
    k1, k2 = scene.camera1.intrinsics, scene.camera2.intrinsics
    focal = (k1[0, 0] + k2[0, 0]) / 2
    stacked, _ = cv2.findEssentialMat(
        normalised(k1, taps.landmarks1[:landmarks]),
        normalised(k2, taps.landmarks2[:landmarks]),
        focal=1.0,
        pp=(0.0, 0.0),
        method=cv2.RANSAC,
        threshold=RANSAC_SIGMAS * sigma / focal,
    )
    if stacked is None or len(stacked) == 0:
        return Outcome(math.inf, failure="no_solution")
    roots = np.asarray(stacked, dtype=np.float64).reshape(-1, 3, 3)
    errors = [pixel_error(k2 @ np.linalg.svd(e)[0][:, 2], scene.epipole2) for e in roots]
    return Outcome(min(errors))


def exact_roots_true_k(scene: PhoneScene, taps: Taps, _sigma: float) -> Outcome:
    """Every rotation of the three-landmark solver on the first three taps and the e1 tap, at
    the **true** intrinsics (principal points included), and the error of the root nearest
    the truth: what 3 + e1 can give at best, since with no landmark to spare every estimator
    returns one of these roots."""
    k1, k2 = scene.camera1.intrinsics, scene.camera2.intrinsics
    rays1 = np.column_stack([normalised(k1, taps.landmarks1[:3]), np.ones(3)])
    rays2 = np.column_stack([normalised(k2, taps.landmarks2[:3]), np.ones(3)])
    friend2 = np.append(normalised(k1, taps.epipole1[None])[0], 1.0)
    rotations = rotations_from_three(friend2, rays1, rays2)
    if not rotations:
        return Outcome(math.inf, failure="no_solution")
    return Outcome(
        min(pixel_error(k2 @ (-rotation @ friend2), scene.epipole2) for rotation in rotations)
    )


def with_e1(landmarks: int, cameras: Cameras = "unknown") -> PhoneMethod:
    """``solve`` on the first ``landmarks`` taps and the e1 tap, told ``cameras``."""
    return lambda s, t, sigma: ours(s, t, sigma, landmarks, given="e1", cameras=cameras)


# --- 1. accuracy against OpenCV -----------------------------------------------------------------

EXACT_3 = "exact roots 3+e1, true K (best root by oracle)"
OPENCV_5 = "OpenCV 5-point essential, 5, true K (best root by oracle)"
OPENCV_E8 = "OpenCV essential (RANSAC), 8, true K"
OPENCV_F8 = "OpenCV 8-point, 8"
PHONE_METHODS: dict[str, PhoneMethod] = {
    **{f"projective {n}+e1": with_e1(n) for n in (5, 8)},
    **{f"phone prior {n}+e1": with_e1(n, "phone") for n in (3, 4, 5, 8)},
    **{f"EXIF focal {n}+e1": with_e1(n, "exif") for n in (3, 4, 5)},
    EXACT_3: exact_roots_true_k,
    OPENCV_5: lambda s, t, sigma: opencv_essential(s, t, sigma, 5),
    OPENCV_E8: lambda s, t, sigma: opencv_essential(s, t, sigma, 8),
    OPENCV_F8: lambda s, t, _: opencv(s, t, 8, cv2.FM_8POINT),
}
CAMERA_AWARE = tuple(name for name in PHONE_METHODS if name.startswith(("phone", "EXIF")))
OURS = tuple(name for name in PHONE_METHODS if not name.startswith(("OpenCV", "exact")))

PhoneTable = dict[float, dict[str, Summary]]


def accuracy(trials: int) -> PhoneTable:
    """Per sigma and method, the e2 error over the same phone scenes and the same taps."""
    return {
        sigma: summaries(PHONE_METHODS, draws("phone", sigma, trials)) for sigma in PHONE_SIGMAS
    }


def accuracy_tables(table: PhoneTable) -> str:
    sigmas = list(table)
    errors = markdown_table(
        ["method (landmarks + given)", *(f"sigma {s:g} px" for s in sigmas)],
        [[name, *(errors_cell(table[s][name]) for s in sigmas)] for name in PHONE_METHODS],
    )
    honesty = markdown_table(
        [
            "method",
            *(f"95 % coverage, {s:g} px" for s in sigmas),
            *(f"failures, {s:g} px" for s in sigmas),
            f"answered by the projective route ({' / '.join(f'{s:g}' for s in sigmas)} px)",
        ],
        [
            [
                name,
                *(coverage_cell(table[s][name]) for s in sigmas),
                *(failures(table[s][name]) for s in sigmas),
                " / ".join(str(fell_back(table[s][name])) for s in sigmas)
                if name in CAMERA_AWARE
                else "-",
            ]
            for name in OURS
        ],
    )
    opencv_failures = markdown_table(
        ["reference method", *(f"failures, {s:g} px" for s in sigmas)],
        [
            [name, *(failures(table[s][name]) for s in sigmas)]
            for name in PHONE_METHODS
            if name not in OURS
        ],
    )
    return f"{errors}\n\n{honesty}\n\n{opencv_failures}"


# --- 2. zoomed photos without EXIF ----------------------------------------------------------------

ZOOM_METHODS: dict[str, PhoneMethod] = {
    "phone prior 4+e1": with_e1(4, "phone"),
    "phone prior 5+e1": with_e1(5, "phone"),
    "projective 5+e1": with_e1(5),
    "phone prior 8+e1": with_e1(8, "phone"),
    "projective 8+e1": with_e1(8),
}

ZoomTable = dict[float, dict[str, Summary]]


def zoomed(trials: int) -> ZoomTable:
    """Per zoom of photo 2 and method, at TARGET_SIGMA: the same scenes and taps."""
    return {
        zoom: summaries(ZOOM_METHODS, draws(f"zoom{zoom:g}", TARGET_SIGMA, trials))
        for zoom in ZOOMS
    }


def zoom_table(table: ZoomTable) -> str:
    return markdown_table(
        [
            "photo 2 zoom",
            "method (landmarks + given)",
            "median / p90 (px)",
            "95 % coverage",
            "answered by the projective route",
            "failures",
        ],
        [
            [
                f"{zoom:g}x",
                name,
                errors_cell(s),
                coverage_cell(s),
                str(fell_back(s)) if name.startswith("phone") else "-",
                failures(s),
            ]
            for zoom, row in table.items()
            for name, s in row.items()
        ],
    )


# --- 3. coverage of the camera-aware route, case by case ----------------------------------------

Source = Literal["phone", "mixed", "zoom2", "zoom3", "prior"]


@dataclass(frozen=True)
class Case(Row):
    """One row: the taps (which scenes, which noise), how many landmarks, what else."""

    given: Given
    cameras: Cameras = "phone"
    source: Source = "phone"


COVERAGE_CASES = (
    *(Case(f"phone prior: {n} + e1", n, "e1") for n in (3, 4, 5, 8)),
    *(Case(f"EXIF focal: {n} + e1", n, "e1", cameras="exif") for n in (3, 5)),
    *(Case(f"phone prior: {n} + e1 + e2 (both marked)", n, "both") for n in (1, 3)),
    Case("phone prior: 6 + line", 6, "line"),
    Case("phone prior: 7, nothing marked", 7, "none"),
    *(Case(f"phone prior: {n} + e1, mixed precision", n, "e1", source="mixed") for n in (4, 5, 8)),
    *(
        Case(f"phone prior: {n} + e1, focal lengths drawn from the prior", n, "e1", source="prior")
        for n in (3, 4, 5, 8)
    ),
    Case("phone prior: 5 + e1, photo 2 zoomed 2x", 5, "e1", source="zoom2"),
    Case("phone prior: 5 + e1, photo 2 zoomed 3x", 5, "e1", source="zoom3"),
)

CoverageTable = dict[Case, Summary]


def coverage(trials: int) -> CoverageTable:
    """Every case at TARGET_SIGMA on its trials' scenes and taps; the ``phone`` cases share
    the scenes and taps of section 1 (trial i is the same), ``mixed`` the same scenes with
    taps of mixed precision, the zoomed ones the scenes and taps of section 2, ``prior``
    scenes whose two focal lengths are drawn from the phone prior."""
    outcomes: dict[Case, list[Outcome]] = {case: [] for case in COVERAGE_CASES}
    for trial in range(trials):
        scene, taps, angle = phone_trial("phone", TARGET_SIGMA, trial)
        mixed, told = mixed_taps(scene, tap_rng("mixed", TARGET_SIGMA, trial), MIXED_SIGMAS)
        # Per source: the scene, its taps, the line's angle, the taps' sigma, their own.
        sources: dict[str, tuple[PhoneScene, Taps, float, float, Precisions | None]] = {
            "phone": (scene, taps, angle, TARGET_SIGMA, None),
            "mixed": (scene, mixed, angle, min(MIXED_SIGMAS), told),
        }
        for stream in (*(f"zoom{z:g}" for z in ZOOMS), "prior"):
            sources[stream] = (*phone_trial(stream, TARGET_SIGMA, trial), TARGET_SIGMA, None)
        for case in COVERAGE_CASES:
            case_scene, case_taps, case_angle, sigma, precisions = sources[case.source]
            outcome = ours(
                case_scene,
                case_taps,
                sigma,
                case.landmarks,
                given=case.given,
                line_angle=case_angle,
                cameras=case.cameras,
                precisions=precisions,
            )
            outcomes[case].append(outcome)
    return {case: Summary.of(found) for case, found in outcomes.items()}


def coverage_table(table: CoverageTable) -> str:
    return cases_table("trials", ((case.label, str(s.trials), s) for case, s in table.items()))


# --- targets ------------------------------------------------------------------------------------


def error_target(summary: Summary, label: str, median: float, p90: float) -> Target:
    passed = summary.median <= median and summary.p90 <= p90
    return passed, (
        f"{verdict(passed)}: phone scenes, {label} at {TARGET_SIGMA:g} px: median <= {median:g} px "
        f"and p90 <= {p90:g} px ({fmt(summary.median)} / {fmt(summary.p90)} px, "
        f"{summary.trials} trials; 95 % intervals {interval(summary.median_interval)} / "
        f"{interval(summary.p90_interval)} px)"
    )


def accuracy_targets(table: PhoneTable) -> list[Target]:
    """The issue's targets at 3 px. An answer that is no point (a curve only, behind
    friend 2) or a refusal counts as infinitely wrong, so "a point" is part of each."""
    row = table[TARGET_SIGMA]
    four = row["phone prior 4+e1"]
    four_passed, four_line = error_target(four, "4 + e1 with the phone prior", 10.0, 30.0)
    three_passed, three_line = error_target(
        row["EXIF focal 3+e1"], "3 + e1 with the EXIF focal length", 15.0, 50.0
    )
    best = row[EXACT_3]
    return [
        error_target(row["phone prior 5+e1"], "5 + e1 with the phone prior", 7.0, 20.0),
        (
            four_passed,
            f"{four_line}; a point in {four.points} of {four.trials} answers "
            f"(failures: {failures(four)})",
        ),
        (
            three_passed,
            f"{three_line}; the best exact root at the true intrinsics, chosen by oracle, gives "
            f"{fmt(best.median)} / {fmt(best.p90)} px on the same taps: with no landmark to "
            "spare, no estimator does better than that",
        ),
    ]


def zoom_target(table: ZoomTable) -> Target:
    aware, plain = table[2.0]["phone prior 5+e1"], table[2.0]["projective 5+e1"]
    passed = aware.p90 <= plain.p90
    return passed, (
        f"{verdict(passed)}: photo 2 zoomed 2x without EXIF, 5 + e1 at {TARGET_SIGMA:g} px on "
        f"the same taps: camera-aware (phone prior) p90 <= projective p90 ({fmt(aware.p90)} px "
        f"vs {fmt(plain.p90)} px; medians {fmt(aware.median)} vs {fmt(plain.median)} px)"
    )
