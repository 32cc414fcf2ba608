"""The five-landmark closed form's fast path answers and refuses exactly as its checked path.

``epipole_from_five`` skips the full validation when a cheap test on its own brackets and
triangle areas says the input is far from every degeneracy. These tests force the checked
path (validation, then every frame) and compare: same ``e2`` on well-spread input, same
refusal (code and message) on input near each tolerance of ``validation.landmark_pairs``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from shared_solver import SolverError, epipole_from_five, validation
from shared_solver.minimal import five_point
from shared_solver.minimal.five_point import cremona_batch
from testbed.scenes import facing_scene, tap

Outcome = np.ndarray | tuple[str, str]  # e2, or the refusal's code and message


def outcome(e1: object, p: object, q: object) -> Outcome:
    try:
        return epipole_from_five(e1, p, q)  # type: ignore[arg-type]
    except SolverError as error:
        return error.code.value, error.message


def both_paths(
    monkeypatch: pytest.MonkeyPatch, e1: object, p: object, q: object
) -> tuple[Outcome, Outcome]:
    """(fast, checked): the default call, and the same with the full checks forced."""
    fast = outcome(e1, p, q)
    with monkeypatch.context() as patched:
        patched.setattr(five_point, "_may_be_degenerate", lambda *_: True)
        checked = outcome(e1, p, q)
    return fast, checked


def assert_same(fast: Outcome, checked: Outcome) -> None:
    if isinstance(checked, np.ndarray):
        assert isinstance(fast, np.ndarray), fast
        np.testing.assert_allclose(fast, checked, rtol=1e-12, atol=1e-15)
    else:
        assert fast == checked


def unit(rng: np.random.Generator) -> np.ndarray:
    direction = rng.normal(size=2)
    return direction / np.linalg.norm(direction)


@pytest.mark.parametrize("sigma", [0.0, 1.0, 3.0])
def test_fast_and_checked_paths_agree_on_noisy_taps(
    monkeypatch: pytest.MonkeyPatch, sigma: float
) -> None:
    rng = np.random.default_rng(11)
    for _ in range(150):
        taps = tap(facing_scene(rng, 8), sigma, rng)
        e1, p, q = taps.epipole1, taps.landmarks1[:5].copy(), taps.landmarks2[:5].copy()
        homogeneous = np.append(e1, 1.0) * rng.uniform(-3.0, 3.0)
        at_infinity = np.append(unit(rng), 0.0)
        for friend2 in (e1, homogeneous, at_infinity, e1.tolist()):
            fast, checked = both_paths(monkeypatch, friend2, p, q)
            assert isinstance(fast, np.ndarray)
            assert_same(fast, checked)


def test_fast_and_checked_paths_agree_on_random_points(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(12)
    for _ in range(300):
        e1 = rng.uniform(-3000.0, 3000.0, 2)
        p, q = rng.uniform(0.0, 1600.0, (5, 2)), rng.uniform(0.0, 1200.0, (5, 2))
        assert_same(*both_paths(monkeypatch, e1, p, q))


Case = tuple[np.ndarray, np.ndarray, np.ndarray]  # e1, p, q
# Each builds input within about ``factor`` times the exact tolerance of one refusal.
Near = Callable[[np.random.Generator, np.ndarray, np.ndarray, np.ndarray, float], Case]


def nudged(
    rng: np.random.Generator, points: np.ndarray, i: int, j: int, factor: float
) -> np.ndarray:
    """``points`` with #i moved to within about ``factor`` times the repeat tolerance of #j."""
    points[i] = points[j] + factor * 1e-9 * validation.spread(points) * unit(rng)
    return points


def on_a_line(rng: np.random.Generator, through: np.ndarray, factor: float) -> np.ndarray:
    """Five points within about ``factor`` times the collinearity tolerance of a line."""
    along = unit(rng)
    across = np.array([-along[1], along[0]])
    return (
        through
        + np.outer(rng.uniform(-600.0, 600.0, 5), along)
        + np.outer(rng.uniform(-1.0, 1.0, 5), across) * (factor * 1e-9 * 1200.0)
    )


def repeated_with_friend2_far(
    rng: np.random.Generator, e1: np.ndarray, p: np.ndarray, q: np.ndarray, factor: float
) -> Case:
    p = nudged(rng, p, 3, 0, factor)
    return e1 + unit(rng) * 10 ** rng.uniform(4.0, 8.0), p, q


def along_friend2_at_infinity(
    rng: np.random.Generator, e1: np.ndarray, p: np.ndarray, q: np.ndarray, factor: float
) -> Case:
    along = unit(rng)
    landmarks = p[0] + np.outer(rng.uniform(-600.0, 600.0, 5), along)
    landmarks += np.outer(rng.uniform(-1.0, 1.0, 5), [-along[1], along[0]]) * factor * 1e-9
    return np.append(along * rng.uniform(0.1, 10.0), 0.0), landmarks, q


def sub_pixel_photos(
    rng: np.random.Generator, e1: np.ndarray, p: np.ndarray, q: np.ndarray, factor: float
) -> Case:
    p, q = p[0] + rng.uniform(-0.3, 0.3, (5, 2)), q[0] + rng.uniform(-0.3, 0.3, (5, 2))
    p[4] = p[1] + factor * 1e-9 * unit(rng)
    return e1, p, q


NEAR: dict[str, Near] = {
    "repeated_in_photo1": lambda rng, e1, p, q, f: (e1, nudged(rng, p, 4, 1, f), q),
    "repeated_in_photo2": lambda rng, e1, p, q, f: (e1, p, nudged(rng, q, 3, 0, f)),
    "repeated_with_friend2_far": repeated_with_friend2_far,
    "friend2_on_landmark": lambda rng, e1, p, q, f: (nudged(rng, p.copy(), 0, 2, f)[0], p, q),
    "collinear_in_photo1": lambda rng, e1, p, q, f: (e1, on_a_line(rng, p[0], f), q),
    "collinear_in_photo2": lambda rng, e1, p, q, f: (e1, p, on_a_line(rng, q[0], f)),
    "on_a_line_through_friend2": lambda rng, e1, p, q, f: (e1, on_a_line(rng, e1, f), q),
    "along_friend2_at_infinity": along_friend2_at_infinity,
    "sub_pixel_photos": sub_pixel_photos,
}


@pytest.mark.parametrize("near", NEAR.values(), ids=NEAR.keys())
def test_near_degenerate_input_gets_the_checked_answer_or_refusal(
    monkeypatch: pytest.MonkeyPatch, near: Near
) -> None:
    rng = np.random.default_rng(13)
    refusals = 0
    for n in range(200):
        taps = tap(facing_scene(np.random.default_rng(n), 8), 1.0, rng)
        e1, p, q = taps.epipole1.copy(), taps.landmarks1[:5].copy(), taps.landmarks2[:5].copy()
        fast, checked = both_paths(monkeypatch, *near(rng, e1, p, q, 10 ** rng.uniform(-1.5, 1.5)))
        assert_same(fast, checked)
        refusals += not isinstance(checked, np.ndarray)
    assert refusals > 0  # the input does reach the tolerance of the full checks


def test_batch_matches_one_at_a_time() -> None:
    rng = np.random.default_rng(14)
    e1s, ps, qs = [], [], []
    for _ in range(100):
        taps = tap(facing_scene(rng, 8), 1.0, rng)
        e1s.append(np.append(taps.epipole1, 1.0))
        ps.append(taps.landmarks1[:5])
        qs.append(taps.landmarks2[:5])
    batch = cremona_batch(np.array(e1s), np.array(ps), np.array(qs))
    for e2, e1, p, q in zip(batch, e1s, ps, qs, strict=True):
        one = epipole_from_five(e1, p, q)
        np.testing.assert_allclose(e2 / np.linalg.norm(e2) * np.sign(e2[2]), one, rtol=1e-12)
