"""Four landmarks and friend 2's position: the conic friend 1 stands on (paper 3.1)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from .. import linalg, validation
from ..projective import Array, hartley_normaliser, homogeneous, transform


def conic_from_cross_ratio(e1: Array, p: Array, q: Array) -> Array:
    """The conic of paper eq. (3) in the coordinates of ``q``, without checks.

    Args:
        e1: (3,) position of friend 2 in photo 1, homogeneous.
        p, q: (4, 3) homogeneous landmarks i, j, k, l of photo 1 and photo 2.

    Returns:
        (3, 3) symmetric C, unit Frobenius norm, with ``e2^T C e2 = 0`` and ``q_s^T C q_s = 0``.
    """
    # The pairs (ij, kl, ik, jl) of the paper's indices i, j, k, l = 0, 1, 2, 3. In plain
    # floats: a few dozen products, where numpy's per-call cost would be most of the time.
    e = e1.tolist()
    rows1, rows2 = p.tolist(), q.tolist()
    pairs = ((0, 1), (2, 3), (0, 2), (1, 3))
    # Brackets |e1 p_a p_b| = e1 . (p_a x p_b).
    ij, kl, ik, jl = (_dot(e, _cross(rows1[i], rows1[j])) for i, j in pairs)
    a, b = ij * kl, ik * jl
    # |e2 q_a q_b| = e2 . (q_a x q_b): each bracket is a linear form in e2.
    l_ij, l_kl, l_ik, l_jl = (_cross(rows2[i], rows2[j]) for i, j in pairs)
    half = [
        [a * (u * v) - b * (w * z) for v, z in zip(l_jl, l_kl, strict=True)]
        for u, w in zip(l_ik, l_ij, strict=True)
    ]
    c = [[half[r][k] + half[k][r] for k in range(3)] for r in range(3)]
    size = math.sqrt(sum(value * value for row in c for value in row))
    return np.array(c) / size


def _cross(u: list[float], v: list[float]) -> tuple[float, float, float]:
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def _dot(u: list[float], v: tuple[float, float, float]) -> float:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def epipole_conic(e1: ArrayLike, pts1: ArrayLike, pts2: ArrayLike) -> Array:
    """The conic in photo 2 on which friend 1 stands, from 4 landmarks (paper 3.1, eq. 3).

    Equal cross ratios of the four epipolar lines through ``e1`` and through ``e2`` give one
    quadratic equation in ``e2``. The conic also passes through the four landmarks of photo 2.

    Args:
        e1: (2,) pixel or (3,) homogeneous position of friend 2 in photo 1.
        pts1: (4, 2) landmarks in photo 1, pixels.
        pts2: (4, 2) the same landmarks in photo 2, pixels.

    Returns:
        (3, 3) symmetric matrix C (unit Frobenius norm) in photo-2 pixel coordinates with
        ``e2^T C e2 = 0`` for homogeneous ``e2``.

    Raises:
        SolverError: invalid or degenerate input (see :mod:`shared_solver.errors`).
    """
    e1h = validation.point(e1, "e1")
    p, q = validation.landmark_pairs(pts1, pts2, minimum=4, maximum=4, epipole1=e1h)
    t1, t2 = hartley_normaliser(p), hartley_normaliser(q)
    conic = conic_from_cross_ratio(
        t1 @ e1h, transform(t1, homogeneous(p)), transform(t2, homogeneous(q))
    )
    pixel_conic = t2.T @ conic @ t2
    return pixel_conic / linalg.norm(pixel_conic)
