"""The simple facing scenes (:func:`testbed.scenes.facing_scene`: 1600x1200, f = 1400 px,
40 m apart, no camera model): the projective route against OpenCV, and the coverage of every
projective method."""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass

import cv2
import numpy as np
from report import markdown_table, verdict

from shared_solver import SolverError, epipoles_from_six
from testbed.scenes import Scene, Taps, facing_scene, line_through, tap

from .common import (
    Given,
    Outcome,
    Summary,
    cases_table,
    coverage_cell,
    errors_cell,
    failures,
    fmt,
    ours,
    pixel_error,
    scene_rng,
    summaries,
    tap_rng,
)

ACCURACY_SIGMAS = (0.5, 1.0, 2.0, 5.0)
COVERAGE_SIGMAS = (1.0, 2.0)
TARGET_SIGMA = 1.0
RANK_TOLERANCE_PX = 1e-6


def scenes(stream: str, count: int, landmarks: int, *, planar: bool = False) -> list[Scene]:
    return [facing_scene(scene_rng(stream, i), landmarks, planar=planar) for i in range(count)]


def opencv(scene: Scene, taps: Taps, landmarks: int, flag: int) -> Outcome:
    """``cv2.findFundamentalMat`` on the first ``landmarks`` taps, without e1.

    The 7-point method returns 1 or 3 roots; the error is that of the root whose e2 is
    nearest the truth (an oracle no real caller has, so this flatters OpenCV).
    """
    stacked, _ = cv2.findFundamentalMat(
        taps.landmarks1[:landmarks], taps.landmarks2[:landmarks], flag
    )
    if stacked is None or len(stacked) == 0:
        return Outcome(math.inf, failure="no_solution")
    roots = np.asarray(stacked, dtype=np.float64).reshape(-1, 3, 3)
    # e2 is the left null vector of F: F^T e2 = 0.
    errors = [pixel_error(np.linalg.svd(f)[0][:, 2], scene.epipole2) for f in roots]
    return Outcome(min(errors))


# --- accuracy against OpenCV ----------------------------------------------------------------

ACCURACY_METHODS: dict[str, Callable[[Scene, Taps, float], Outcome]] = {
    "ours 5+e1": lambda s, t, sigma: ours(s, t, sigma, 5, given="e1"),
    "ours 6+e1": lambda s, t, sigma: ours(s, t, sigma, 6, given="e1"),
    "ours 8+e1": lambda s, t, sigma: ours(s, t, sigma, 8, given="e1"),
    "OpenCV 7-point, 7 (best root by oracle)": lambda s, t, _: opencv(s, t, 7, cv2.FM_7POINT),
    "OpenCV 8-point, 8": lambda s, t, _: opencv(s, t, 8, cv2.FM_8POINT),
}
OURS = ("ours 5+e1", "ours 6+e1", "ours 8+e1")

AccuracyTable = dict[float, dict[str, Summary]]


def accuracy(trials: int) -> AccuracyTable:
    """Per sigma and method, the e2 error over the same scenes and the same noisy taps."""
    drawn = scenes("accuracy", trials, 8)
    return {
        sigma: summaries(
            ACCURACY_METHODS,
            ((s, tap(s, sigma, tap_rng("accuracy", sigma, i)), sigma) for i, s in enumerate(drawn)),
        )
        for sigma in ACCURACY_SIGMAS
    }


def accuracy_target(table: AccuracyTable) -> tuple[bool, str]:
    ours8 = table[TARGET_SIGMA]["ours 8+e1"].median
    cv8 = table[TARGET_SIGMA]["OpenCV 8-point, 8"].median
    passed = ours8 <= 0.5 * cv8
    return passed, (
        f"{verdict(passed)}: facing scenes, with 8 landmarks + e1 at {TARGET_SIGMA:g} px, "
        f"median e2 error <= half of OpenCV 8-point's on the same 8 landmarks ({fmt(ours8)} px "
        f"vs {fmt(cv8)} px, ratio {ours8 / cv8:.2f})"
    )


def accuracy_tables(table: AccuracyTable) -> str:
    errors = markdown_table(
        ["sigma (px)", *ACCURACY_METHODS],
        [[f"{sigma:g}", *(errors_cell(s) for s in row.values())] for sigma, row in table.items()],
    )
    honesty = markdown_table(
        ["sigma (px)", *(f"failures: {name}" for name in ACCURACY_METHODS)]
        + [f"95 % coverage: {name}" for name in OURS],
        [
            [
                f"{sigma:g}",
                *(failures(s) for s in row.values()),
                *(coverage_cell(row[name]) for name in OURS),
            ]
            for sigma, row in table.items()
        ],
    )
    return f"{errors}\n\n{honesty}"


# --- coverage of every projective method ------------------------------------------------------


@dataclass(frozen=True)
class CoverageCase:
    """One row of the coverage table: a method of ``solve`` and what is given to it."""

    name: str
    landmarks: int
    given: Given
    planar: bool = False

    @property
    def label(self) -> str:
        extra = {"e1": " + e1", "line": " + line", "both": " + e1 + e2", "none": ""}
        return f"{self.name}: {self.landmarks}{extra[self.given]}"


COVERAGE_CASES = (
    CoverageCase("planar", 6, "e1", planar=True),
    CoverageCase("six_point_line", 6, "line"),
    CoverageCase("two_epipoles", 3, "both"),
    CoverageCase("two_epipoles", 5, "both"),
    CoverageCase("seven_point", 7, "none"),
    CoverageCase("eight_point", 8, "none"),
    CoverageCase("eight_point", 12, "none"),
)

CoverageTable = dict[float, dict[CoverageCase, Summary]]


def coverage(trials: int) -> CoverageTable:
    """Per sigma and case: one 12-landmark scene and one set of taps per trial for every
    non-planar case (each uses the first landmarks), a planar 6-landmark scene for planar."""
    general = scenes("coverage", trials, 12)
    floors = scenes("planar", trials, 6, planar=True)
    table = {}
    for sigma in COVERAGE_SIGMAS:
        outcomes: dict[CoverageCase, list[Outcome]] = {case: [] for case in COVERAGE_CASES}
        for trial in range(trials):
            rng = tap_rng("coverage", sigma, trial)
            taps = tap(general[trial], sigma, rng)
            line_angle = float(rng.uniform(0.0, math.pi))
            floor_taps = tap(floors[trial], sigma, tap_rng("planar", sigma, trial))
            for case in COVERAGE_CASES:
                scene, case_taps = (
                    (floors[trial], floor_taps) if case.planar else (general[trial], taps)
                )
                outcomes[case].append(
                    ours(
                        scene,
                        case_taps,
                        sigma,
                        case.landmarks,
                        given=case.given,
                        line_angle=line_angle,
                    )
                )
        table[sigma] = {case: Summary.of(found) for case, found in outcomes.items()}
    return table


def coverage_table(table: CoverageTable) -> str:
    return cases_table(
        "sigma (px)",
        (
            (case.label, f"{sigma:g}", row[case])
            for case in COVERAGE_CASES
            for sigma, row in table.items()
        ),
    )


# --- the six-landmark cubic's ranking on noise-free input --------------------------------------


@dataclass(frozen=True)
class RankCount:
    scenes: int
    rank_one: int
    among_candidates: int
    refused: Counter[str]
    candidates: Counter[int]


def six_point_rank(count: int) -> RankCount:
    """Noise-free 6 landmarks + a line through the true e1: is the rank-1 candidate true?"""
    rank_one = among = 0
    refused: Counter[str] = Counter()
    sizes: Counter[int] = Counter()
    for trial in range(count):
        rng = scene_rng("rank", trial)
        scene = facing_scene(rng, 6)
        line = line_through(scene.epipole1, float(rng.uniform(0.0, math.pi)))
        try:
            candidates = epipoles_from_six(
                line,
                scene.landmarks1,
                scene.landmarks2,
                **scene.sizes,
            )
        except SolverError as error:
            refused[error.code.value] += 1
            continue
        sizes[len(candidates)] += 1
        right = [pixel_error(c.epipole2, scene.epipole2) <= RANK_TOLERANCE_PX for c in candidates]
        rank_one += right[0]
        among += any(right)
    return RankCount(count, rank_one, among, refused, sizes)


def rank_lines(rank: RankCount) -> str:
    sizes = ", ".join(f"{v} with {k}" for k, v in sorted(rank.candidates.items()))
    refused = ", ".join(f"{v} {k}" for k, v in rank.refused.items()) or "0"
    return (
        f"`epipoles_from_six` on noise-free facing scenes (6 landmarks + a line through the "
        f"true e1 in a random direction), {rank.scenes} scenes: the rank-1 candidate is the "
        f"true one (e2 within {RANK_TOLERANCE_PX:g} px) in **{rank.rank_one} / {rank.scenes}**; "
        f"the true one is among the candidates in {rank.among_candidates} / {rank.scenes}; "
        f"refused: {refused}; scenes by number of real candidates: {sizes}."
    )
