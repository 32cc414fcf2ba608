"""The real calibrated temple photos (Middlebury templeSparseRing): the facing pair 3 / 6."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from shared_solver.estimation.uncertainty import contains
from testbed.scenes import solved, tap, temple_cameras, temple_scene

PAIR = ("templeSR0003", "templeSR0006")


def test_calibration_gives_the_published_epipoles(temple_parameters: Path) -> None:
    cameras = temple_cameras(temple_parameters)
    assert len(cameras) == 16
    s = temple_scene(temple_parameters, *PAIR, 5, np.random.default_rng(0))
    # The values the dataset notes list for this pair.
    assert np.allclose(s.epipole1, [522.8, 384.1], atol=0.05)
    assert np.allclose(s.epipole2, [522.2, 73.9], atol=0.05)


def test_exact_temple_landmarks_give_the_exact_friend(temple_parameters: Path) -> None:
    rng = np.random.default_rng(1)
    for n in (4, 5, 6, 8):
        s = temple_scene(temple_parameters, *PAIR, n, rng)
        result = solved(s)
        if n == 4:
            conic = np.array(result.conic2)
            x = np.append(s.epipole2, 1.0)
            assert abs(x @ conic @ x) / np.linalg.norm(2 * (conic @ x)[:2]) < 1e-6
        else:
            assert result.epipole2 is not None
            assert np.linalg.norm(np.array(result.epipole2) - s.epipole2) < 1e-6


def test_tapped_temple_landmarks_find_the_friend_within_the_ellipse(
    temple_parameters: Path,
) -> None:
    """Taps with 1 px noise on 640x480 photos: the truth is inside the 95 % ellipse about
    95 % of the time, and the typical error is a few pixels."""
    rng = np.random.default_rng(2)
    for n in (5, 8):
        hits, errors = 0, []
        trials = 300
        for _ in range(trials):
            s = temple_scene(temple_parameters, *PAIR, n, rng)
            taps = tap(s, 1.0, rng)
            result = solved(s, taps, tap_sigma=1.0)
            if result.epipole2 is None:  # no position claimed: a miss for coverage
                errors.append(np.inf)
                continue
            assert result.uncertainty is not None
            assert result.uncertainty.covariance is not None
            answer = np.array(result.epipole2)
            errors.append(float(np.linalg.norm(answer - s.epipole2)))
            hits += contains(answer, np.array(result.uncertainty.covariance), s.epipole2)
        median = np.median(errors)
        print(f"temple {n} landmarks: coverage {hits / trials:.3f}, median error {median:.1f} px")
        assert 0.90 <= hits / trials <= 0.99
        assert np.median(errors) < (25 if n == 5 else 10)
