"""At the limit: every camera-aware case against the Cramér-Rao bound of its own taps
(:mod:`testbed.bound`), the camera model's false alarms, and the plane model on 3-D scenes.

For each phone scene and tap noise (the scenes and taps of section 1: trial i is the same),
each case's error is divided by the bound of that scene: the **median ratio** is the median
error over the median of the bound's medians, the **RMS ratio** the root mean square of
error / bound RMS (1.0 is the limit; a few wild answers show here first), the **area ratio**
the median of the 95 % region's area over the bound's 95 % ellipse. A **false alarm** is an
honest search (a phone scene, Gaussian taps) told that its taps do not (quite) fit two
phone photos.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field
from unittest import mock

import numpy as np
from report import markdown_table, verdict

from shared_solver import SolverError, WarningCode
from shared_solver.answers import projective as projective_answers
from shared_solver.estimation.camera import KNOWN_FOCAL_UNCERTAINTY, PHONE_LOG_SIGMA
from testbed.bound import Bound, CameraPrior, Marks, SceneBounds
from testbed.phones import PhoneScene
from testbed.scenes import Taps

from .common import (
    CHI2_2DOF_95,
    Cameras,
    Given,
    Row,
    Target,
    ellipse_covers,
    fmt,
    percent,
    percentile,
    solve_call,
)
from .phones import phone_trial

LIMIT_SIGMAS = (1.0, 3.0, 8.0)
TARGET_SIGMAS = (3.0, 8.0)  # where the RMS, coverage and area targets apply
RMS_TARGET = 1.25
COVERAGE_TARGET = (0.93, 0.97)
AREA_TARGET = 1.1
FALSE_ALARM_TARGET = 0.001
_DISAGREES = (WarningCode.CAMERA_MODEL_DISAGREES, WarningCode.CAMERA_MODEL_UNSURE)


@dataclass(frozen=True)
class Case(Row):
    given: Given
    cameras: Cameras

    @property
    def priors(self) -> tuple[CameraPrior, CameraPrior]:
        prior = {"phone": PHONE_LOG_SIGMA, "exif": KNOWN_FOCAL_UNCERTAINTY, "unknown": None}
        return prior[self.cameras], prior[self.cameras]

    @property
    def marks(self) -> Marks:
        return "both" if self.given == "both" else "e1"


CASES = (
    *(Case(f"phone prior: {n} + e1", n, "e1", "phone") for n in (3, 4, 5, 8)),
    *(Case(f"EXIF focal: {n} + e1", n, "e1", "exif") for n in (3, 4, 5)),
    *(Case(f"phone prior: {n} + e1 + e2 (both marked)", n, "both", "phone") for n in (1, 3)),
    *(Case(f"camera unknown: {n} + e1", n, "e1", "unknown") for n in (5, 6, 8)),
)


@dataclass
class Cell:
    """One case at one tap noise, over the trials."""

    errors: list[float] = field(default_factory=list)  # px, inf for no point
    bound_medians: list[float] = field(default_factory=list)
    scaled: list[float] = field(default_factory=list)  # error / bound RMS, answers with a point
    areas: list[float] = field(default_factory=list)  # region / bound's, answers with one
    held: list[bool] = field(default_factory=list)
    # ... whether the region, its size set to AREA_TARGET x the bound's area (knowing the
    # truth's bound: an oracle), would hold the truth: what any region of its shape can do
    held_at_target_area: list[bool] = field(default_factory=list)
    false_alarms: int = 0
    planes: int = 0  # answers of the plane model
    plane_misses: int = 0  # ... whose region missed the truth where the general one's held
    failures: Counter[str] = field(default_factory=Counter)

    @property
    def trials(self) -> int:
        return len(self.errors)

    def median_ratio(self) -> float:
        return _median(self.errors) / _median(self.bound_medians)

    def rms_ratio(self) -> float:
        finite = [z for z in self.scaled if math.isfinite(z)]
        return math.sqrt(sum(z * z for z in finite) / len(finite)) if finite else math.inf

    def coverage(self) -> float:
        return sum(self.held) / len(self.held) if self.held else math.nan

    def area_ratio(self) -> float:
        return _median(self.areas) if self.areas else math.nan

    def coverage_at_target_area(self) -> float:
        held = self.held_at_target_area
        return sum(held) / len(held) if held else math.nan


LimitTable = dict[float, dict[Case, Cell]]


def _median(values: list[float]) -> float:
    return float(np.median(np.asarray(values, dtype=np.float64))) if values else math.nan


def limit(trials: int) -> LimitTable:
    """Every case at every sigma on the same scenes and taps as section 1."""
    table: LimitTable = {sigma: {case: Cell() for case in CASES} for sigma in LIMIT_SIGMAS}
    for trial in range(trials):
        scene, _, _ = phone_trial("phone", LIMIT_SIGMAS[0], trial)
        kinds: tuple[tuple[bool, Marks], ...] = ((True, "e1"), (True, "both"), (False, "e1"))
        bounds = {
            (modelled, marks): SceneBounds(scene, modelled=modelled, marks=marks)
            for modelled, marks in kinds
        }
        for sigma in LIMIT_SIGMAS:
            scene, taps, _ = phone_trial("phone", sigma, trial)
            for case in CASES:
                modelled = case.cameras != "unknown"
                bound = bounds[(modelled, case.marks)].bound(case.landmarks, sigma, case.priors)
                _record(table[sigma][case], case, scene=scene, taps=taps, sigma=sigma, bound=bound)
    return table


def _record(
    cell: Cell, case: Case, *, scene: PhoneScene, taps: Taps, sigma: float, bound: Bound
) -> None:
    truth = scene.epipole2
    cell.bound_medians.append(bound.median)
    try:
        result = solve_call(
            scene,
            taps,
            sigma,
            case.landmarks,
            given=case.given,
            cameras=case.cameras,
        )
    except SolverError as refusal:
        cell.errors.append(math.inf)
        cell.failures[refusal.code.value] += 1
        return
    if result.epipole2 is None:
        cell.errors.append(math.inf)
        cell.failures["no point"] += 1
    else:
        error = float(np.linalg.norm(np.array(result.epipole2) - truth))
        cell.errors.append(error)
        cell.scaled.append(error / bound.rms)
    covered = ellipse_covers(result, truth)
    if covered is not None:
        cell.held.append(covered)
        assert result.uncertainty is not None
        assert result.uncertainty.covariance is not None
        assert result.uncertainty.ellipse is not None
        covariance = np.array(result.uncertainty.covariance)
        determinant = float(np.linalg.det(covariance))
        area = math.sqrt(max(determinant, 0.0) / np.linalg.det(bound.covariance))
        cell.areas.append(area)
        if area > 0.0:
            offset = truth - np.asarray(result.uncertainty.ellipse.center)
            distance = float(offset @ np.linalg.solve(covariance, offset))
            cell.held_at_target_area.append(distance <= CHI2_2DOF_95 * AREA_TARGET / area)
    cell.false_alarms += any(warning.code in _DISAGREES for warning in result.warnings)
    if result.method == "planar":
        cell.planes += 1
        if covered is not True:
            cell.plane_misses += _general_holds(case, scene=scene, taps=taps, sigma=sigma)


def _general_holds(case: Case, *, scene: PhoneScene, taps: Taps, sigma: float) -> bool:
    """Whether the general answer's region (the plane model switched off) holds the truth:
    then the plane model should not have answered."""
    with mock.patch.object(projective_answers, "coplanar_fit", return_value=None):
        result = solve_call(scene, taps, sigma, case.landmarks, given=case.given)
    return ellipse_covers(result, scene.epipole2) is True


def limit_table(table: LimitTable) -> str:
    return markdown_table(
        [
            "case (landmarks + given)",
            "tap noise",
            "median / p90 (px)",
            "bound's median (px)",
            "median ratio",
            "RMS ratio",
            "95 % coverage",
            "area ratio",
            "told the model does not fit",
            "failures",
        ],
        [
            [
                case.label,
                f"{sigma:g} px",
                f"{fmt(_median(cell.errors))} / {fmt(percentile(cell.errors, 90))}",
                fmt(_median(cell.bound_medians)),
                f"{cell.median_ratio():.2f}",
                f"{cell.rms_ratio():.2f}",
                f"{percent(cell.coverage())} of {len(cell.held)}" if cell.held else "-",
                f"{cell.area_ratio():.2f}" if cell.areas else "-",
                f"{cell.false_alarms} of {cell.trials}" if case.cameras != "unknown" else "-",
                ", ".join(f"{n} {code}" for code, n in cell.failures.most_common()) or "0",
            ]
            for sigma, row in table.items()
            for case, cell in row.items()
        ],
    )


def limit_targets(table: LimitTable) -> list[Target]:
    """The issue's targets at 3 and 8 px (false alarms at 1, 3 and 8 px), 1000 trials."""
    cells = [(sigma, case, cell) for sigma, row in table.items() for case, cell in row.items()]
    at_targets = [(s, c, cell) for s, c, cell in cells if s in TARGET_SIGMAS]
    modelled = [(s, c, cell) for s, c, cell in at_targets if c.cameras != "unknown"]
    worst_rms = max(modelled, key=lambda x: x[2].rms_ratio())
    rms_passed = worst_rms[2].rms_ratio() <= RMS_TARGET
    low, high = COVERAGE_TARGET
    claimed = [(s, c, cell) for s, c, cell in at_targets if cell.held]
    off = [(s, c, cell) for s, c, cell in claimed if not low <= cell.coverage() <= high]
    coverages = [cell.coverage() for _, _, cell in claimed]
    wide = [(s, c, cell) for s, c, cell in claimed if cell.area_ratio() > AREA_TARGET]
    areas = [cell.area_ratio() for _, _, cell in claimed]
    alarms = [(s, c, cell) for s, c, cell in cells if c.cameras != "unknown"]
    worst_alarm = max(alarms, key=lambda x: x[2].false_alarms / x[2].trials)
    alarm_rate = worst_alarm[2].false_alarms / worst_alarm[2].trials
    total_alarms = sum(cell.false_alarms for _, _, cell in alarms)
    total_searches = sum(cell.trials for _, _, cell in alarms)
    planes = sum(cell.planes for _, _, cell in cells)
    misses = sum(cell.plane_misses for _, _, cell in cells)
    trials = worst_rms[2].trials
    return [
        (
            rms_passed,
            f"{verdict(rms_passed)}: RMS error <= {RMS_TARGET:g}x the bound's in every phone "
            f"case at {' and '.join(f'{s:g}' for s in TARGET_SIGMAS)} px (worst: "
            f"{worst_rms[2].rms_ratio():.2f}, {worst_rms[1].label} at {worst_rms[0]:g} px; "
            f"{trials} trials per case)",
        ),
        (
            not off,
            f"{verdict(not off)}: the 95 % region holds the truth {percent(low)}-"
            f"{percent(high)} of the time in every case at "
            f"{' and '.join(f'{s:g}' for s in TARGET_SIGMAS)} px ({percent(min(coverages))}-"
            f"{percent(max(coverages))}"
            + (
                "; outside: "
                + ", ".join(
                    f"{c.label} at {s:g} px {percent(cell.coverage())}" for s, c, cell in off
                )
                if off
                else ""
            )
            + ")",
        ),
        (
            not wide,
            f"{verdict(not wide)}: the region's area <= {AREA_TARGET:g}x the bound's "
            f"(median) in every case at {' and '.join(f'{s:g}' for s in TARGET_SIGMAS)} px "
            f"({min(areas):.2f}-{max(areas):.2f}"
            + "".join(
                f"; {c.label} at {s:g} px: {cell.area_ratio():.2f}, and its regions sized to "
                f"{AREA_TARGET:g}x the bound's area, knowing it, would hold the truth "
                f"{percent(cell.coverage_at_target_area())} of the time"
                for s, c, cell in wide
            )
            + ")",
        ),
        (
            alarm_rate <= FALSE_ALARM_TARGET,
            f"{verdict(alarm_rate <= FALSE_ALARM_TARGET)}: honest phone taps told they do not "
            f"fit two phone photos at most {percent(FALSE_ALARM_TARGET)} of the time in every "
            f"camera-aware case at {', '.join(f'{s:g}' for s in LIMIT_SIGMAS)} px (worst: "
            f"{worst_alarm[2].false_alarms} of {worst_alarm[2].trials}, {worst_alarm[1].label} "
            f"at {worst_alarm[0]:g} px; {total_alarms} of {total_searches} in all)",
        ),
        (
            misses == 0,
            f"{verdict(misses == 0)}: the plane model never chosen on 3-D scenes where the "
            f"general one's region holds the truth and its own does not (chosen {planes} "
            f"times in {sum(cell.trials for _, c, cell in cells if c.cameras == 'unknown')} "
            f"camera-unknown searches; {misses} such)",
        ),
    ]
