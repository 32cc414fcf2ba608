"""Noisy taps: both five-landmark routes agree, and answers do not depend on the pixel frame."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from shared_solver import epipole_from_five, solve
from testbed.scenes import facing_scene, pixel, tap


def similarity(angle: float, scale: float, shift: tuple[float, float]) -> np.ndarray:
    c, s = math.cos(angle) * scale, math.sin(angle) * scale
    return np.array([[c, -s, shift[0]], [s, c, shift[1]], [0.0, 0.0, 1.0]])


def apply(matrix: np.ndarray, points: np.ndarray) -> np.ndarray:
    mapped = np.column_stack([points, np.ones(len(points))]) @ matrix.T
    return mapped[:, :2] / mapped[:, 2:]


def same_point(a: np.ndarray, b: np.ndarray, tolerance_px: float) -> bool:
    """Equal homogeneous points: within tolerance in pixels, or as directions when far off."""
    a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
    b = b if a @ b >= 0 else -b
    if abs(a[2]) > 1e-4 and abs(b[2]) > 1e-4:
        return bool(
            np.linalg.norm(pixel(a) - pixel(b))
            <= tolerance_px * max(1.0, float(np.linalg.norm(pixel(a))) / 1e4)
        )
    return bool(np.linalg.norm(a - b) < 1e-9)


@pytest.mark.parametrize("sigma", [0.5, 2.0, 5.0])
def test_cremona_and_linear_agree_on_noisy_taps(sigma: float) -> None:
    rng = np.random.default_rng(7)
    for _ in range(300):
        taps = tap(facing_scene(rng, 5), sigma, rng)
        cremona = epipole_from_five(taps.epipole1, taps.landmarks1, taps.landmarks2)
        linear = epipole_from_five(taps.epipole1, taps.landmarks1, taps.landmarks2, method="linear")
        assert same_point(cremona, linear, 1e-6)


noise = st.sampled_from([0.0, 1.0, 3.0])
angles = st.floats(-math.pi, math.pi)
scales = st.floats(0.2, 5.0)
shifts = st.tuples(st.floats(-3000, 3000), st.floats(-3000, 3000))


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10_000), noise, angles, scales, shifts, angles, scales, shifts)
def test_five_point_answer_moves_with_either_photo(
    seed: int,
    sigma: float,
    a1: float,
    s1: float,
    t1: tuple[float, float],
    a2: float,
    s2: float,
    t2: tuple[float, float],
) -> None:
    """A minimal solver commutes with any similarity of photo 1 and of photo 2."""
    rng = np.random.default_rng(seed)
    taps = tap(facing_scene(rng, 5), sigma, rng)
    m1, m2 = similarity(a1, s1, t1), similarity(a2, s2, t2)
    moved = epipole_from_five(
        apply(m1, taps.epipole1[None])[0], apply(m1, taps.landmarks1), apply(m2, taps.landmarks2)
    )
    original = epipole_from_five(taps.epipole1, taps.landmarks1, taps.landmarks2)
    assert same_point(moved, m2 @ original, 1e-6 * s2)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), angles, shifts, angles, shifts, scales)
def test_least_squares_answer_moves_with_either_photo(
    seed: int, a1: float, t1: tuple[float, float], a2: float, t2: tuple[float, float], scale: float
) -> None:
    """Maximum likelihood is invariant to moving or rotating either photo, and to scaling
    both photos and the tap noise together; the ellipse moves with the answer."""
    rng = np.random.default_rng(seed)
    s = facing_scene(rng, 8)
    taps = tap(s, 1.0, rng)
    m1, m2 = similarity(a1, scale, t1), similarity(a2, scale, t2)
    original = solve(taps.landmarks1, taps.landmarks2, epipole1=taps.epipole1, tap_sigma=1.0)
    moved = solve(
        apply(m1, taps.landmarks1),
        apply(m2, taps.landmarks2),
        epipole1=apply(m1, taps.epipole1[None])[0],
        tap_sigma=scale,
    )
    assert original.method == moved.method
    assert original.epipole2 is not None
    assert moved.epipole2 is not None
    expected = apply(m2, np.array([original.epipole2]))[0]
    assert np.linalg.norm(np.array(moved.epipole2) - expected) <= 1e-4 * scale
    assert original.uncertainty is not None
    assert moved.uncertainty is not None
    before, after = original.uncertainty.ellipse, moved.uncertainty.ellipse
    assert before is not None
    assert after is not None
    assert np.allclose(np.array(after.axes), scale * np.array(before.axes), rtol=1e-3)
    if before.axes[0] > 1.05 * before.axes[1]:  # the orientation of a round ellipse is arbitrary
        turned = (before.angle_deg + math.degrees(a2) - after.angle_deg) % 180.0
        assert min(turned, 180.0 - turned) < 0.5
    assert np.allclose(original.residuals, np.array(moved.residuals) / scale, atol=1e-4)


def test_more_landmarks_give_better_answers() -> None:
    """The least-squares fit over 8 landmarks beats the minimal five on the same taps."""
    rng = np.random.default_rng(11)
    errors: dict[int, list[float]] = {5: [], 8: []}
    for _ in range(200):
        s = facing_scene(rng, 8)
        taps = tap(s, 1.0, rng)
        for n, found in errors.items():
            result = solve(
                taps.landmarks1[:n], taps.landmarks2[:n], epipole1=taps.epipole1, tap_sigma=1.0
            )
            off = result.epipole2 is None  # far off, or not pinned down: an infinite error
            found.append(
                np.inf if off else float(np.linalg.norm(np.array(result.epipole2) - s.epipole2))
            )
    assert np.median(errors[8]) < 0.6 * np.median(errors[5])
