"""Parametric bootstrap: how far an answer moves when the taps are made again.

First-order propagation is too optimistic where the answer depends strongly on the taps
(a minimal set of landmarks, no redundancy to average noise out, near a degenerate layout).
There the ellipse keeps its first-order shape but its size is set so that it holds LEVEL of
the answers re-solved from the taps with fresh noise of the same sigma, and never shrinks
below first order. The seed is fixed: the same taps always give the same ellipse.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..minimal.five_point import cremona_batch
from ..projective import Array
from .uncertainty import CHI2_2D, LEVEL

SAMPLES = 200  # closed form, vectorised
RESOLVES = 100  # one full solve each
_SEED = 2017


def scale(answer: Array, covariance: Array, samples: Array) -> float:
    """Factor (>= 1) by which to multiply ``covariance`` so its ellipse holds LEVEL of samples.

    Args:
        answer: (2,) the answer in pixels; covariance: (2, 2) its first-order covariance.
        samples: (K, 2) re-solved answers; NaN or infinite rows (no answer) count as outside.
    """
    with np.errstate(invalid="ignore", over="ignore"):
        offsets = samples - answer
        distances = np.einsum("ki,ij,kj->k", offsets, np.linalg.inv(covariance), offsets)
    distances[~np.isfinite(distances)] = np.inf
    return max(1.0, float(np.quantile(distances, LEVEL)) / CHI2_2D)


def five_point_samples(e1: Array, p: Array, q: Array, sigma: float) -> Array:
    """(SAMPLES, 2) answers of the paper's closed form for re-made taps (e1 (2,), p, q (5, 2))."""
    rng = np.random.default_rng(_SEED)
    e1s = np.column_stack([e1 + rng.normal(0.0, sigma, (SAMPLES, 2)), np.ones(SAMPLES)])
    p_s = p + rng.normal(0.0, sigma, (SAMPLES, *p.shape))
    q_s = q + rng.normal(0.0, sigma, (SAMPLES, *q.shape))
    homogeneous = cremona_batch(e1s, p_s, q_s)
    with np.errstate(divide="ignore", invalid="ignore"):
        return homogeneous[:, :2] / homogeneous[:, 2:]


def resolved_samples(resolve: Callable[[np.random.Generator], Array]) -> Array:
    """(RESOLVES, 2) answers of ``resolve`` (re-made taps -> answer in pixels, NaN if none)."""
    rng = np.random.default_rng(_SEED)
    return np.array([resolve(rng) for _ in range(RESOLVES)])
