"""The 95 % ellipse is a claim: over many noisy trials it must hold the truth about 95 % of
the time, neither much less (overconfident) nor nearly always (useless)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from shared_solver import solve
from shared_solver.answers.building import calibrated
from shared_solver.estimation import bootstrap
from shared_solver.estimation.least_squares import gauge_free_covariance
from shared_solver.estimation.uncertainty import CHI2_2D, contains, ellipse
from testbed.scenes import facing_scene, solved, tap

TRIALS = 500


def covered(
    result_covariance: tuple[tuple[float, float], tuple[float, float]] | None,
    answer: tuple[float, float] | None,
    truth: np.ndarray,
) -> bool:
    """Inside the claimed region; no region claimed counts as a miss."""
    if result_covariance is None or answer is None:
        return False
    return contains(np.array(answer), np.array(result_covariance), truth)


@pytest.mark.parametrize(("landmarks", "sigma"), [(5, 1.0), (5, 2.0), (6, 1.0), (8, 1.0), (8, 2.0)])
def test_ellipse_holds_the_truth_about_95_percent_of_the_time(
    landmarks: int, sigma: float, record_property: Callable[[str, object], None]
) -> None:
    rng = np.random.default_rng(landmarks * 100 + int(sigma * 10))
    hits = 0
    for _ in range(TRIALS):
        s = facing_scene(rng, landmarks)
        taps = tap(s, sigma, rng)
        result = solved(s, taps, tap_sigma=sigma)
        assert result.uncertainty is not None
        hits += covered(result.uncertainty.covariance, result.epipole2, s.epipole2)
    coverage = hits / TRIALS
    record_property("coverage", coverage)
    print(
        f"coverage of the 95 % ellipse, {landmarks} landmarks + e1, sigma {sigma}: {coverage:.3f}"
    )
    assert 0.90 <= coverage <= 0.99


def test_ellipse_matches_the_reported_axes() -> None:
    """The ellipse fields describe the covariance: axes^2 = 5.99 * eigenvalues."""
    rng = np.random.default_rng(1)
    s = facing_scene(rng, 8)
    taps = tap(s, 1.0, rng)
    result = solve(taps.landmarks1, taps.landmarks2, epipole1=taps.epipole1, tap_sigma=1.0)
    assert result.uncertainty is not None
    ellipse, covariance = result.uncertainty.ellipse, np.array(result.uncertainty.covariance)
    assert ellipse is not None
    assert result.uncertainty.level == 0.95
    assert ellipse.center == result.epipole2
    a, b = ellipse.axes
    assert a >= b
    assert np.allclose(sorted([a * a, b * b]), CHI2_2D * np.linalg.eigvalsh(covariance))
    angle = np.radians(ellipse.angle_deg)
    major = np.array([np.cos(angle), np.sin(angle)])
    assert np.isclose(major @ covariance @ major, a * a / CHI2_2D)


def test_a_needle_thin_region_keeps_its_width() -> None:
    """A region 1e5 px long and a few thousandths of a px wide (found by drawing absurd
    requests: a photo of 0.0016 x 0.0012 px): the short axis is the covariance's, not 0.
    The textbook eigenvalue, the mean less the half gap, cancels to 0 there, and a region
    of no width is a false certainty."""
    long, short = 469581.0 / np.sqrt(CHI2_2D), 0.00373 / np.sqrt(CHI2_2D)
    turn = np.radians(90.0000002)
    axis = np.array([np.cos(turn), np.sin(turn)])
    across = np.array([-axis[1], axis[0]])
    covariance = long**2 * np.outer(axis, axis) + short**2 * np.outer(across, across)
    _, (a, b), angle = ellipse(np.zeros(2), covariance)
    assert a == pytest.approx(469581.0, rel=1e-9)
    assert b == pytest.approx(0.00373, rel=1e-3)
    assert angle == pytest.approx(90.0, abs=1e-5)


def test_a_round_region_keeps_its_axes_in_order() -> None:
    """A circle of any size: its two axes are equal, the first never the shorter (rounded
    apart, they once swapped, and the region of a scaled request was dropped)."""
    for exponent in np.linspace(-12.0, 12.0, 97):
        sigma = 1.7 * 10.0**exponent
        _, (a, b), _ = ellipse(np.zeros(2), sigma**2 * np.eye(2))
        assert 0.0 < b <= a
        assert b == pytest.approx(a, rel=1e-12)


@pytest.mark.parametrize("scale", [1.0, 1e6, 1e-6])
def test_a_nearly_flat_fit_gets_its_true_covariance_at_every_scale(scale: float) -> None:
    """A Jacobian flat along its gauge, its other singular values from 1 down to 1e-8 (J^T J
    conditioned at 1e16, as a plane fit near a degenerate layout was): the covariance is
    symmetric and its largest variance 1 / s_min^2, at any scale of the residuals. Inverting
    J^T J gave 5e13 at one scale and 1.3e16 at another (found by drawing scaled photos)."""
    rng = np.random.default_rng(3)
    gauge = rng.normal(size=9)
    gauge /= np.linalg.norm(gauge)
    basis = np.linalg.qr(np.column_stack([gauge, rng.normal(size=(9, 8))]))[0]
    columns = np.linalg.qr(rng.normal(size=(12, 8)))[0]
    jacobian = columns @ np.diag(np.logspace(0, -8, 8)) @ basis[:, 1:].T
    covariance = gauge_free_covariance(jacobian * scale, gauge, 1.0) * scale**2
    np.testing.assert_allclose(covariance, covariance.T, rtol=0, atol=1e-12 * 1e16)
    assert np.linalg.eigvalsh(covariance)[-1] == pytest.approx(1e16, rel=1e-6)
    assert abs(gauge @ covariance @ gauge) < 1e-6 * 1e16


def test_quality_follows_the_uncertainty() -> None:
    """Sloppy taps (sigma 8 px) on 5 landmarks are rarely 'good'; precise taps on 12 usually are."""
    rng = np.random.default_rng(2)
    grades: dict[str, list[str]] = {"sloppy": [], "precise": []}
    for _ in range(100):
        s = facing_scene(rng, 12)
        for name, n, sigma in (("sloppy", 5, 8.0), ("precise", 12, 0.5)):
            taps = tap(s, sigma, rng)
            result = solve(
                taps.landmarks1[:n],
                taps.landmarks2[:n],
                epipole1=taps.epipole1,
                tap_sigma=sigma,
                **s.sizes,
            )
            grades[name].append(result.quality)
    assert grades["sloppy"].count("good") < 30
    assert grades["precise"].count("good") > 80
    poor = [g for g in grades["sloppy"] if g == "poor"]
    assert poor, "a very uncertain answer must be graded poor"


def test_bootstrap_scale_is_the_quantile_of_the_re_solved_answers() -> None:
    rng = np.random.default_rng(5)
    samples = rng.normal(size=(200, 2)) * [3.0, 1.0]
    covariance = np.diag([9.0, 1.0])
    distances = np.einsum("ki,ij,kj->k", samples, np.linalg.inv(covariance), samples)
    expected = max(1.0, float(np.quantile(distances, 0.95)) / CHI2_2D)
    assert bootstrap.scale(np.zeros(2), covariance, samples) == pytest.approx(expected, rel=1e-12)
    # Twice as spread as claimed: the region grows to hold 95 % of them.
    grown = float(np.quantile(4.0 * distances, 0.95)) / CHI2_2D
    assert grown > 3.0
    assert bootstrap.scale(np.zeros(2), covariance / 4.0, samples) == pytest.approx(
        grown, rel=1e-12
    )


def test_no_region_when_re_made_taps_too_often_give_no_answer() -> None:
    """More than 5 % of the bootstrap's answers missing: no ellipse could hold 95 % of them,
    so the answer claims none (rather than a region of first-order size)."""
    samples = np.zeros((100, 2))
    samples[:10] = np.nan
    assert bootstrap.scale(np.zeros(2), np.eye(2), samples) == np.inf
    covariance = np.eye(2)
    assert calibrated(np.array([0.0, 0.0, 1.0]), covariance, lambda: samples) is None
    samples[3:10] = 0.0  # 3 % missing: still calibrated
    assert calibrated(np.array([0.0, 0.0, 1.0]), covariance, lambda: samples) is not None
