"""Six landmarks and a line through the buddy: both epipoles (paper 3.3).

With ``e1 = s a + t b`` on the given line, the 9x9 system of six landmark equations
``q^T F p = 0`` and the three equations ``F e1 = 0`` is singular exactly when its
determinant, a homogeneous cubic in ``(s, t)``, vanishes. Every real root gives a geometry
that fits the six landmarks exactly; the true one is among them. Ranking them is not this
solver's job (:mod:`shared_solver.estimation.ranking`).
"""

from __future__ import annotations

import numpy as np

from .. import linalg, words
from ..errors import ErrorCode, SolverError
from ..polynomial import binary_cubic_roots
from ..projective import (
    Array,
    canonical,
    canonical_matrix,
    hartley_normaliser,
    homogeneous,
    transform,
)

# Sample angles for the cubic: (cos, sin) pairs spread over half a turn, and the matrix
# taking the cubic's values there to its coefficients.
_ANGLES = np.pi * np.arange(4) / 4
_COS, _SIN = np.cos(_ANGLES), np.sin(_ANGLES)
_FROM_SAMPLES = np.linalg.inv(np.column_stack([_COS**3, _COS**2 * _SIN, _COS * _SIN**2, _SIN**3]))


def six_point_line_roots(line: Array, p: Array, q: Array) -> list[tuple[Array, Array, Array]]:
    """Every geometry with the buddy on ``line`` that fits 6 landmarks, unranked.

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
    landmark_rows = np.einsum("ni,nj->nij", q_n, p_n).reshape(6, 9)

    def systems(e1: Array) -> Array:
        """(K, 9, 9): the six landmark rows, then (F e1)_r for each (K, 3) buddy position."""
        stacked = np.zeros((len(e1), 9, 9))
        stacked[:, :6] = landmark_rows
        for row in range(3):  # row r of F e1 = 0 involves F's r-th row only
            stacked[:, 6 + row, 3 * row : 3 * row + 3] = e1
        return stacked

    samples = np.outer(_COS, a) + np.outer(_SIN, b)
    roots = _real_roots(np.linalg.det(systems(samples)))
    if not roots:
        return []
    positions = np.array([s * a + t * b for s, t in roots])
    _, singular, vt = np.linalg.svd(systems(positions))
    found = []
    for e1_n, values, null in zip(positions, singular, vt[:, -1], strict=True):
        if values[-2] <= 1e-9 * values[0]:
            continue  # more than one F: this root does not fix the geometry
        fundamental = t2.T @ null.reshape(3, 3) @ t1
        fundamental = fundamental / linalg.norm(fundamental)
        left, values_f, _ = linalg.svd(fundamental)
        if values_f[1] <= 1e-9:
            continue  # rank below 2: no epipoles
        found.append(
            (
                canonical(linalg.solve(t1, e1_n)),
                canonical(left[:, 2]),  # F^T e2 = 0
                canonical_matrix(fundamental),
            )
        )
    return found


def _real_roots(samples: Array) -> list[tuple[float, float]]:
    """Real roots (s, t), unit norm, of the homogeneous cubic sampled at ``_ANGLES``."""
    # det(s a + t b) = k0 s^3 + k1 s^2 t + k2 s t^2 + k3 t^3
    k0, k1, k2, k3 = (_FROM_SAMPLES @ samples).tolist()
    if max(abs(k0), abs(k1), abs(k2), abs(k3)) == 0:
        raise SolverError(
            ErrorCode.DEGENERATE_CONFIGURATION,
            words.LINE_FITS_EVERYWHERE,
        )
    return binary_cubic_roots(k0, k1, k2, k3)
