"""A phone zoomed across the venue (2x, 3x, 5x) with no EXIF, told only that it is a phone:
a landmark more never makes the median answer worse, the regions hold the truth at least
90 % of the time, and no answer better than 'poor' puts the friend far outside its region
(the same on real cameras: tests/solver/test_real_cameras.py)."""

from __future__ import annotations

import functools
import itertools

import numpy as np
import pytest

from shared_solver import SolverError, solve
from shared_solver.estimation.uncertainty import CHI2_2D, chi2_quantile
from testbed.phones import phone_scene
from testbed.scenes import tap

SIGMA = 3.0
SCENES = 60
COUNTS = range(3, 9)
WORSE = 1.05  # as on real cameras: medians of a few hundred move by a few percent
FAR_OUTSIDE = chi2_quantile(0.9999, 2)


@functools.cache
def _answers(zoom: float) -> dict[int, list[tuple[float, float | None, str]]]:
    """(error px, squared distance of the truth in the region or None, quality) by landmark
    count, on the same scenes and taps (each count uses the first ones)."""
    found: dict[int, list[tuple[float, float | None, str]]] = {n: [] for n in COUNTS}
    for seed in range(SCENES):
        rng = np.random.default_rng((int(zoom * 10), seed))
        scene = phone_scene(rng, max(COUNTS), zoom2=zoom)
        taps = tap(scene, SIGMA, rng)
        for count in COUNTS:
            try:
                result = solve(
                    taps.landmarks1[:count],
                    taps.landmarks2[:count],
                    epipole1=taps.epipole1,
                    tap_sigma=SIGMA,
                    camera1="phone",
                    camera2="phone",
                    **scene.sizes,
                )
            except SolverError:
                found[count].append((np.inf, None, "refused"))
                continue
            if result.epipole2 is None:
                found[count].append((np.inf, None, result.quality))
                continue
            offset = np.array(result.epipole2) - scene.epipole2
            covariance = None if result.uncertainty is None else result.uncertainty.covariance
            distance = None
            if covariance is not None:
                distance = float(offset @ np.linalg.solve(np.array(covariance), offset))
            found[count].append((float(np.linalg.norm(offset)), distance, result.quality))
    return found


@pytest.mark.parametrize("zoom", [2.0, 3.0, 5.0])
def test_a_zoomed_photo_gets_better_with_every_landmark_and_stays_honest(zoom: float) -> None:
    answers = _answers(zoom)
    medians = [np.median([error for error, _, _ in answers[n]]) for n in COUNTS]
    for fewer, more in itertools.pairwise(medians):
        assert more <= WORSE * fewer, medians
    every = [answer for found in answers.values() for answer in found]
    claimed = [distance for _, distance, _ in every if distance is not None]
    assert len(claimed) >= 0.8 * len(every)
    assert np.mean([distance <= CHI2_2D for distance in claimed]) >= 0.90
    confident = [d for _, d, quality in every if d is not None and quality != "poor"]
    assert max(confident) <= FAR_OUTSIDE
