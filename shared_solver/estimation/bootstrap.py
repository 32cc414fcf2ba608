"""Parametric bootstrap: how far an answer moves when the taps are made again.

First-order propagation is too optimistic where the answer depends strongly on the taps
(a minimal set of landmarks, no redundancy to average noise out, near a degenerate layout).
There the ellipse keeps its first-order shape but its size is set so that it holds LEVEL of
the answers re-solved from the taps with fresh noise of each tap's own covariance, and
never shrinks below first order. The seed is fixed: the same taps always give the same ellipse.
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import numpy as np

from .. import linalg
from ..linalg import cholesky2
from ..minimal.five_point import cremona_batch
from ..projective import Array
from .camera import FocalPrior
from .pinhole.fit import PinholeFit
from .pinhole.model import PinholeModel
from .pinhole.predictions import friend1_positions
from .taps import Taps
from .uncertainty import CHI2_2D, LEVEL

SAMPLES = 200  # closed form, vectorised
PINHOLE_SAMPLES = 64  # a few Gauss-Newton steps each, all at once
RESOLVES = 100  # one full solve each
_CHORD_STEPS = 2  # Gauss-Newton steps after the first, for the pinhole samples
_SEED = 2017


def scale(answer: Array, covariance: Array, samples: Array) -> float:
    """Factor (>= 1) by which to multiply ``covariance`` so its ellipse holds LEVEL of samples;
    infinite when more than 1 - LEVEL of them have no answer (no region can hold them).

    Args:
        answer: (2,) the answer in pixels; covariance: (2, 2) its first-order covariance.
        samples: (K, 2) re-solved answers; NaN or infinite rows (no answer) count as outside.
    """
    with np.errstate(invalid="ignore", over="ignore"):
        offsets = samples - answer
        distances = np.einsum("ki,ij,kj->k", offsets, linalg.inv(covariance), offsets)
    distances[~np.isfinite(distances)] = np.inf
    return max(1.0, _quantile(distances, LEVEL) / CHI2_2D)


def _quantile(values: Array, level: float) -> float:
    """``np.quantile(values, level)`` (linear interpolation) by a partial sort: a tenth of
    its cost on a few dozen values, and this runs in every solve with a bootstrap."""
    position = level * (len(values) - 1)
    low = int(position)
    high = min(low + 1, len(values) - 1)
    ordered = np.partition(values, (low, high))
    below, above = float(ordered[low]), float(ordered[high])
    if above == below or position == low:
        return below
    return below + (position - low) * (above - below)


def five_point_samples(taps: Taps) -> Array:
    """(SAMPLES, 2) answers of the paper's closed form for re-made taps (5 landmarks + e1)."""
    assert taps.epipole1 is not None
    assert taps.cov_e1 is not None
    noise = _noise(((SAMPLES, 2), (SAMPLES, *taps.p.shape), (SAMPLES, *taps.q.shape)))
    e1s = np.column_stack([_remade(taps.epipole1, taps.cov_e1, noise[0]), np.ones(SAMPLES)])
    homogeneous = cremona_batch(
        e1s, _remade(taps.p, taps.cov_p, noise[1]), _remade(taps.q, taps.cov_q, noise[2])
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        return homogeneous[:, :2] / homogeneous[:, 2:]


def pinhole_samples(fit: PinholeFit, taps: Taps, priors: tuple[FocalPrior, FocalPrior]) -> Array:
    """(PINHOLE_SAMPLES, 2) answers of the pinhole model for re-made taps.

    Each is refined from the fit on its own taps by Gauss-Newton steps with the fit's own
    Jacobian (the chord method, all samples at once): the taps' and friend 1's nonlinearity
    are kept. One step was not enough: where the focal lengths are left to their priors
    (three or four landmarks) a straight step along them leaves the curved valley in which
    friend 1 stays put, and the samples flew off (measured at 1 px: regions twice the
    bound's area); the further steps bring them back to it.
    """
    pairs = ((taps.epipole1, taps.cov_e1), (taps.epipole2, taps.cov_e2))
    marks = [(mark, cov) for mark, cov in pairs if mark is not None and cov is not None]
    # Every tap re-made in one go (one Cholesky factorisation of all their covariances):
    # the landmarks of photo 1, of photo 2, then the marks, as rows.
    remade = _remade(
        np.concatenate([taps.p, taps.q, *(mark[None] for mark, _ in marks)]),
        np.concatenate([taps.cov_p, taps.cov_q, *(cov[None] for _, cov in marks)]),
        _stacked_noise(len(taps), len(marks)),
    )
    n = len(taps)
    remade_marks = iter(remade[:, 2 * n :].transpose(1, 0, 2))
    epipole1, epipole2 = (
        None if mark is None or cov is None else next(remade_marks) for mark, cov in pairs
    )
    model = PinholeModel(
        taps,
        priors,
        p=remade[:, :n],
        q=remade[:, n : 2 * n],
        epipole1=epipole1,
        epipole2=epipole2,
        readings=None if taps.gravity is None else _reading_noise(),
    )
    # The Gauss-Newton step -(J^T J)^-1 J^T r for every row r, with the fit's (J^T J)^-1.
    gain = fit.jacobian @ fit.covariance
    steps = -model.offsets(fit.pose) @ gain
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        for _ in range(_CHORD_STEPS):
            steps = steps - model.offsets(fit.pose.after_steps(steps)) @ gain
    return friend1_positions(fit.pose.after_steps(steps), fit.centres[1])


def resolved_samples(taps: Taps, resolve: Callable[[Taps], Array]) -> Array:
    """(RESOLVES, 2) answers of ``resolve`` (re-made taps -> answer in pixels, NaN if none)."""
    rng = np.random.default_rng(_SEED)
    return np.array([resolve(taps.retapped(rng)) for _ in range(RESOLVES)])


def _remade(points: Array, covariance: Array | None, noise: Array) -> Array:
    """(count, *points.shape) the points with fresh noise of their covariances ((2, 2) for
    one point, (N, 2, 2) for N), from standard normal ``noise`` (count, *points.shape)."""
    assert covariance is not None
    factor = cholesky2(covariance)
    # L n for every draw n as two columns of L scaled: numpy's einsum with an ellipsis
    # costs several times as much on these few numbers.
    return points + (noise[..., :1] * factor[..., 0] + noise[..., 1:] * factor[..., 1])


@functools.lru_cache(maxsize=32)
def _stacked_noise(landmarks: int, marks: int) -> Array:
    """(PINHOLE_SAMPLES, 2 landmarks + marks, 2) the draws of :func:`_noise` for the
    landmarks of photo 1, of photo 2 and the friends' marks, side by side: the same numbers
    as re-making each kind of tap on its own."""
    count = PINHOLE_SAMPLES
    shapes = ((count, landmarks, 2), (count, landmarks, 2)) + ((count, 2),) * marks
    p, q, *friends = _noise(shapes)
    stacked = np.concatenate([p, q, *(friend[:, None] for friend in friends)], axis=1)
    stacked.setflags(write=False)
    return stacked


@functools.lru_cache(maxsize=1)
def _reading_noise() -> Array:
    """(PINHOLE_SAMPLES, 3) standard normal draws re-making the phones' readings (gravity's
    two residuals, the compass's), from a seed of their own: the taps' draws stay as they
    were."""
    draws = np.random.default_rng(_SEED + 1).normal(size=(PINHOLE_SAMPLES, 3))
    draws.setflags(write=False)
    return draws


@functools.lru_cache(maxsize=32)
def _noise(shapes: tuple[tuple[int, ...], ...]) -> tuple[Array, ...]:
    """Standard normal draws of these shapes, in order, from the fixed seed: the same every
    call (so the same taps always give the same ellipse), drawn once per layout of taps."""
    rng = np.random.default_rng(_SEED)
    draws = tuple(rng.normal(size=shape) for shape in shapes)
    for draw in draws:
        draw.setflags(write=False)
    return draws
