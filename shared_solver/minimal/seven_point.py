"""Seven landmarks, no epipole: the classical 7-point method (OpenCV).

``F = a F1 + (1 - a) F2`` over the 2-D null space of the seven equations ``q^T F p = 0``,
and ``det F = 0`` is a cubic in ``a``: one or three real geometries (Hartley & Zisserman
11.1.2). OpenCV's ``findFundamentalMat(..., FM_7POINT)`` solves it; it is a well-kept
implementation, so this file only unpacks its roots.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..projective import Array, canonical_matrix, left_epipole, right_epipole


def seven_point_roots(p: Array, q: Array) -> list[tuple[Array, Array, Array]]:
    """Every geometry that fits 7 landmarks exactly, unranked.

    Args:
        p, q: (7, 2) checked landmarks of photo 1 and photo 2, pixels.

    Returns:
        ``(e1, e2, F)`` per real root: (3,) unit epipoles, (3, 3) F (unit norm, largest
        entry positive). Empty when OpenCV finds none.
    """
    stacked, _ = cv2.findFundamentalMat(p, q, cv2.FM_7POINT)
    if stacked is None:
        return []
    roots = [canonical_matrix(f) for f in np.asarray(stacked, dtype=np.float64).reshape(-1, 3, 3)]
    return [(right_epipole(f), left_epipole(f), f) for f in roots]
