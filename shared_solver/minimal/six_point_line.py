"""Six landmarks and a line through friend 2: both epipoles (paper 3.3).

The six landmark equations ``q^T F p = 0`` leave a 3-dimensional family
``F = x F1 + y F2 + z F3``. With ``e1 = s a + t b`` on the given line, ``F e1 = 0`` is the
3x3 system ``(s A + t B) (x, y, z) = 0`` (the columns of A are ``F_k a``, those of B
``F_k b``), which has a solution exactly when the homogeneous cubic ``det(s A + t B)``
vanishes: the paper's 9x9 determinant, factored through the landmarks' null space. Every
real root gives a geometry that fits the six landmarks exactly; the true one is among them.
Ranking them is not this solver's job (:mod:`shared_solver.estimation.ranking`).
"""

from __future__ import annotations

import numpy as np

from .. import linalg
from ..errors import Reason
from ..polynomial import binary_cubic_roots
from ..projective import (
    Array,
    canonical,
    canonical_matrix,
    hartley_normaliser,
    homogeneous,
    transform,
)
from ..refusal import SolverError

# Singular values this small against the largest are zero: the landmarks' equations leave
# more than a 3-dimensional family of F, or a root's 3x3 system leaves more than one F.
_RANK_TOLERANCE = 1e-9


def six_point_line_roots(line: Array, p: Array, q: Array) -> list[tuple[Array, Array, Array]]:
    """Every geometry with friend 2 on ``line`` that fits 6 landmarks, unranked.

    Args:
        line: (3,) checked line ``(a, b, c)``, ``a x + b y + c = 0`` in photo-1 pixels.
        p, q: (6, 2) checked landmarks of photo 1 and photo 2, pixels.

    Returns:
        ``(e1, e2, F)`` per real root: (3,) canonical epipoles and (3, 3) F (unit norm,
        largest entry positive), in the order of the roots. Empty when no root fixes F.

    Raises:
        SolverError: every point of the line fits (degenerate).
    """
    t1, t2 = hartley_normaliser(p), hartley_normaliser(q)
    p_n, q_n = transform(t1, homogeneous(p)), transform(t2, homogeneous(q))
    line_n = linalg.solve(t1.T, line)  # lines map by the inverse transpose
    # a: the line's point nearest the (normalised) origin; b: its point at infinity.
    a = np.array([-line_n[0] * line_n[2], -line_n[1] * line_n[2], line_n[0] ** 2 + line_n[1] ** 2])
    b = np.array([line_n[1], -line_n[0], 0.0])
    a, b = a / linalg.norm(a), b / linalg.norm(b)
    # The six landmark equations q^T F p = 0 leave F = x F1 + y F2 + z F3.
    _, values, vt = linalg.svd(np.einsum("ni,nj->nij", q_n, p_n).reshape(6, 9))
    if values[5] <= _RANK_TOLERANCE * values[0]:
        return []  # the landmarks leave more than that family: no root can fix F
    family = vt[6:].reshape(3, 3, 3)  # F1, F2, F3
    flat_family = vt[6:]
    to_pixels = linalg.inv(t1)
    # F e1 = 0 with e1 = s a + t b: (s A + t B) (x, y, z) = 0, A's columns F_k a, B's F_k b.
    along_a, along_b = (family @ a).T, (family @ b).T
    roots = _real_roots(along_a, along_b)
    found = []
    for s_, t_ in roots:
        _, values_m, vt_m = linalg.svd(s_ * along_a + t_ * along_b)
        if values_m[1] <= _RANK_TOLERANCE * values_m[0]:
            continue  # more than one F: this root does not fix the geometry
        fundamental = t2.T @ (vt_m[2] @ flat_family).reshape(3, 3) @ t1
        fundamental = fundamental / linalg.norm(fundamental)
        left, values_f, _ = linalg.svd(fundamental)
        if values_f[1] <= 1e-9:
            continue  # rank below 2: no epipoles
        found.append(
            (
                canonical(to_pixels @ (s_ * a + t_ * b)),
                canonical(left[:, 2]),  # F^T e2 = 0
                canonical_matrix(fundamental),
            )
        )
    return found


def _real_roots(first: Array, second: Array) -> list[tuple[float, float]]:
    """Real roots (s, t), unit norm, of the homogeneous cubic ``det(s A + t B)``."""
    # det(s A + t B) = k0 s^3 + k1 s^2 t + k2 s t^2 + k3 t^3: the ends are det A and det B,
    # and det(A + B), det(A - B) give the middle coefficients.
    k0, k3 = _det(first), _det(second)
    plus, minus = _det(first + second), _det(first - second)
    k1, k2 = 0.5 * (plus - minus) - k3, 0.5 * (plus + minus) - k0
    if max(abs(k0), abs(k1), abs(k2), abs(k3)) == 0:
        raise SolverError(Reason.LINE_FITS_EVERYWHERE)
    return binary_cubic_roots(k0, k1, k2, k3)


def _det(m: Array) -> float:
    (a, b, c), (d, e, f), (g, h, i) = m.tolist()
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
