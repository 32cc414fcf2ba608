"""Both friends see each other: F from both epipoles and three or more landmarks.

``F e1 = 0`` and ``F^T e2 = 0`` leave ``F = B2 M B1^T`` with ``B1``, ``B2`` spanning the
planes orthogonal to the epipoles and ``M`` 2x2: the 1-D homography between the two pencils
of epipolar lines (paper, introduction; Hartley & Zisserman 9.2). Each landmark gives one
linear equation on ``M``; three fix it, more give least squares.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .. import linalg, validation
from ..errors import Reason
from ..projective import (
    Array,
    canonical_matrix,
    hartley_normaliser,
    homogeneous,
    orthogonal_complement,
    transform,
    unit,
)
from ..refusal import SolverError


def fundamental_from_epipoles(
    e1: ArrayLike, e2: ArrayLike, pts1: ArrayLike, pts2: ArrayLike
) -> Array:
    """F from both epipoles and N >= 3 landmarks (least squares beyond 3).

    The paper's introduction: the epipoles (4 degrees of freedom) and the 1-D homography
    between the pencils of epipolar lines (3, fixed by three landmarks) make up F.

    Args:
        e1: (2,) pixel or (3,) homogeneous position of friend 2 in photo 1.
        e2: (2,) pixel or (3,) homogeneous position of friend 1 in photo 2.
        pts1, pts2: (N, 2) landmarks in photo 1 and photo 2, pixels, N >= 3.

    Returns:
        (3, 3) F in pixel coordinates, unit Frobenius norm, with ``F e1 = 0``,
        ``F^T e2 = 0`` and ``q^T F p = 0`` (exactly for N = 3, least squares beyond).

    Raises:
        SolverError: invalid or degenerate input.
    """
    e1h, e2h = validation.point(e1, "e1"), validation.point(e2, "e2")
    p, q = validation.landmark_pairs(pts1, pts2, minimum=3, epipole1=e1h, epipole2=e2h)
    return canonical_matrix(fundamental_between(e1h, e2h, p, q))


def fundamental_between(e1: Array, e2: Array, p: Array, q: Array) -> Array:
    """The linear solve of :func:`fundamental_from_epipoles` on checked input."""
    t1, t2 = hartley_normaliser(p), hartley_normaliser(q)
    basis1 = orthogonal_complement(unit(t1 @ e1))
    basis2 = orthogonal_complement(unit(t2 @ e2))
    along1 = transform(t1, homogeneous(p)) @ basis1  # (N, 2)
    along2 = transform(t2, homogeneous(q)) @ basis2  # (N, 2)
    design = np.einsum("ni,nj->nij", along2, along1).reshape(len(p), 4)
    _, singular, vt = linalg.svd(design)
    # Unknowns: 4 entries of M up to scale. Fixed iff the design has rank 3.
    if singular[2] <= 1e-10 * singular[0]:
        raise SolverError(Reason.TOO_FEW_EPIPOLAR_LINES)
    homography = vt[-1].reshape(2, 2)
    return t2.T @ (basis2 @ homography @ basis1.T) @ t1
