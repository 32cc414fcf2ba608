"""Exact taps give exact answers (1e-6 px) in every case the solver handles."""

from __future__ import annotations

import numpy as np
import pytest

from shared_solver import (
    epipole_conic,
    epipole_from_five,
    epipoles_from_six,
    fundamental_from_epipoles,
    solve,
)
from testbed.scenes import Scene, facing_scene, line_through, marks, pixel

EXACT_PX = 1e-6
SEEDS = range(40)


def scene(seed: int, n: int, *, planar: bool = False) -> Scene:
    return facing_scene(np.random.default_rng(seed), n, planar=planar)


def epipolar_distances(fundamental: np.ndarray, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Distance (px) of each q from the epipolar line F p."""
    lines = np.column_stack([p, np.ones(len(p))]) @ np.asarray(fundamental).T
    return np.abs(np.einsum("ni,ni->n", lines[:, :2], q) + lines[:, 2]) / np.hypot(
        lines[:, 0], lines[:, 1]
    )


@pytest.mark.parametrize("seed", SEEDS)
def test_conic_passes_through_friend1_and_the_landmarks(seed: int) -> None:
    s = scene(seed, 4)
    conic = epipole_conic(s.epipole1, s.landmarks1, s.landmarks2)
    assert np.allclose(conic, conic.T)
    for point in [s.epipole2, *s.landmarks2]:
        x = np.append(point, 1.0)
        # Distance-like residual: |x^T C x| / |grad| is the distance to the curve to first order.
        gradient = 2 * (conic @ x)[:2]
        assert abs(x @ conic @ x) / np.linalg.norm(gradient) < EXACT_PX


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("method", ["cremona", "linear"])
def test_five_landmarks_give_friend1_exactly(seed: int, method: str) -> None:
    s = scene(seed, 5)
    e2 = epipole_from_five(s.epipole1, s.landmarks1, s.landmarks2, method=method)  # type: ignore[arg-type]
    assert np.isclose(np.linalg.norm(e2), 1.0)
    assert np.linalg.norm(pixel(e2) - s.epipole2) < EXACT_PX


@pytest.mark.parametrize("seed", SEEDS)
def test_five_landmarks_accept_friend2_in_homogeneous_coordinates(seed: int) -> None:
    s = scene(seed, 5)
    scaled = -3.0 * np.append(s.epipole1, 1.0)
    assert (
        np.linalg.norm(pixel(epipole_from_five(scaled, s.landmarks1, s.landmarks2)) - s.epipole2)
        < EXACT_PX
    )


@pytest.mark.parametrize("seed", SEEDS)
def test_line_and_six_landmarks_contain_the_truth(seed: int) -> None:
    s = scene(seed, 6)
    direction = np.random.default_rng(seed).uniform(0, np.pi)
    line = line_through(s.epipole1, direction)
    candidates = epipoles_from_six(line, s.landmarks1, s.landmarks2, **s.sizes)
    assert [c.rank for c in candidates] == list(range(1, len(candidates) + 1))
    assert len(candidates) in (1, 2, 3)
    errors = [np.linalg.norm(pixel(c.epipole2) - s.epipole2) for c in candidates]
    best = candidates[int(np.argmin(errors))]
    assert min(errors) < EXACT_PX
    assert np.linalg.norm(pixel(best.epipole1) - s.epipole1) < EXACT_PX
    assert abs(line @ best.epipole1) / np.hypot(*line[:2]) < EXACT_PX
    assert epipolar_distances(best.fundamental, s.landmarks1, s.landmarks2).max() < EXACT_PX
    assert best["epipole2"] is best.epipole2  # readable by name like the JSON


@pytest.mark.parametrize("given", ["seven landmarks", "a line and six landmarks"])
def test_the_truth_is_ranked_first_in_most_scenes(given: str) -> None:
    trials = 200
    first = 0
    for seed in range(trials):
        if given == "seven landmarks":
            s = scene(3000 + seed, 7)
            result = solve(s.landmarks1, s.landmarks2, **s.sizes)
            assert 1 <= len(result.candidates) <= 3
            assert result.epipole2 is not None
            top = np.array(result.epipole2)
        else:
            s = scene(1000 + seed, 6)
            line = line_through(s.epipole1, np.random.default_rng(seed).uniform(0, np.pi))
            top = pixel(epipoles_from_six(line, s.landmarks1, s.landmarks2, **s.sizes)[0].epipole2)
        first += bool(np.linalg.norm(top - s.epipole2) < EXACT_PX)
    assert first >= 0.95 * trials, f"truth ranked first in {first}/{trials}"


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("n", [3, 5])
def test_both_epipoles_give_the_fundamental_matrix(seed: int, n: int) -> None:
    s = scene(seed, 8)
    fundamental = fundamental_from_epipoles(
        s.epipole1, s.epipole2, s.landmarks1[:n], s.landmarks2[:n]
    )
    # Checked on all 8 landmarks, 5 of which it never saw when n = 3.
    assert epipolar_distances(fundamental, s.landmarks1, s.landmarks2).max() < EXACT_PX
    assert np.allclose(
        fundamental / np.linalg.norm(fundamental),
        s.fundamental * np.sign(fundamental.ravel() @ s.fundamental.ravel()),
        atol=1e-8,
    )


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize(
    ("landmarks", "given", "method"),
    [
        (4, "e1", "conic"),
        (5, "e1", "five_point_epipole"),
        (6, "e1", "least_squares_epipole"),
        (8, "e1", "least_squares_epipole"),
        (6, "line", "six_point_line"),
        (3, "both", "two_epipoles"),
        (5, "both", "two_epipoles"),
        (7, "none", "seven_point"),
        (8, "none", "eight_point"),
        (12, "none", "eight_point"),
    ],
)
def test_solve_is_exact_on_exact_taps(seed: int, landmarks: int, given: str, method: str) -> None:
    s = scene(seed, landmarks)
    result = solve(s.landmarks1, s.landmarks2, **marks(s, given), **s.sizes)
    assert result.method == method
    if method == "conic":
        assert result.epipole2 is None
        assert result.conic2 is not None
        conic = np.array(result.conic2)
        x = np.append(s.epipole2, 1.0)
        assert abs(x @ conic @ x) / np.linalg.norm(2 * (conic @ x)[:2]) < EXACT_PX
        return
    assert result.epipole2 is not None
    if (
        method in ("six_point_line", "seven_point")
        and np.linalg.norm(np.array(result.epipole2) - s.epipole2) > EXACT_PX
    ):
        # The rank-1 candidate can be a spurious root (test above bounds how often);
        # the truth must then be another candidate.
        assert any(
            c.epipole2 is not None and np.linalg.norm(np.array(c.epipole2) - s.epipole2) < EXACT_PX
            for c in result.candidates
        )
        return
    assert np.linalg.norm(np.array(result.epipole2) - s.epipole2) < EXACT_PX
    assert result.epipole1 is not None
    assert np.linalg.norm(np.array(result.epipole1) - s.epipole1) < EXACT_PX
    assert max(result.residuals) < EXACT_PX
    assert result.fundamental is not None
    assert (
        epipolar_distances(np.array(result.fundamental), s.landmarks1, s.landmarks2).max()
        < EXACT_PX
    )
    assert result.suspect_landmarks == []


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("n", [5, 6, 9])
def test_landmarks_on_the_floor_use_the_plane_and_stay_exact(seed: int, n: int) -> None:
    s = scene(seed, n, planar=True)
    result = solve(s.landmarks1, s.landmarks2, epipole1=s.epipole1, **s.sizes)
    assert result.method == "planar"
    assert result.homography is not None
    assert result.epipole2 is not None
    assert np.linalg.norm(np.array(result.epipole2) - s.epipole2) < EXACT_PX


@pytest.mark.parametrize("seed", SEEDS)
def test_exact_answers_are_certain(seed: int) -> None:
    """Exact taps with a tiny tap_sigma give a tiny ellipse and a good grade."""
    s = scene(seed, 6)
    result = solve(s.landmarks1, s.landmarks2, epipole1=s.epipole1, tap_sigma=1e-3, **s.sizes)
    assert result.uncertainty is not None
    assert result.uncertainty.ellipse is not None
    assert result.uncertainty.ellipse.axes[0] < 1.0
    assert result.quality == "good"
    assert result.warnings == []
