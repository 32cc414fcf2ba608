"""First-order covariances of what a fit predicts, from the covariance of its seven
parameters (:mod:`.pose`): ``C_y = J C J^T`` with ``J`` the derivative of the prediction
(:mod:`.predictions`) along the parameters (Hartley & Zisserman 5.2.1, forward propagation).
"""

from __future__ import annotations

import numpy as np

from ... import linalg
from ...projective import Array
from .pose import Poses, tangent_basis
from .predictions import friend1_pixel, fundamental_stack


def fundamental_covariance(pose: Poses, centres: Array, covariance: Array) -> Array:
    """(9, 9) first-order covariance of F at unit Frobenius norm, read row by row.

    F's derivatives along the 7 parameters, through their (7, 7) ``covariance``, projected
    on the unit sphere (F is kept at unit norm, so it cannot vary along itself). ``pose``: a
    batch of one; ``centres``: (2, 2) principal points of photo 1 and 2, px.
    """
    tangent = np.array(tangent_basis(*pose.friend2[0].tolist()))
    (x1, y1), (x2, y2) = centres.tolist()
    stacked = fundamental_stack(pose, ((x1, y1), (x2, y2)), tangent).reshape(8, 9)
    norm = linalg.norm(stacked[0])
    unit = stacked[0] / norm
    derivatives = stacked[1:].T / norm  # (9, 7)
    jacobian = derivatives - np.outer(unit, unit @ derivatives)
    return jacobian @ covariance @ jacobian.T


def friend1_covariance(pose: Poses, centres: Array, covariance: Array) -> Array | None:
    """(2, 2) px^2 covariance of friend 1's pixel position in photo 2, None if friend 1 is
    at infinity there. ``pose``: a batch of one; ``centres``: (2, 2) principal points of
    photo 1 and 2, px; ``covariance``: (7, 7) of the parameters."""
    centre = (float(centres[1, 0]), float(centres[1, 1]))
    tangent = np.array(tangent_basis(*pose.friend2[0].tolist()))
    position, jacobian = friend1_pixel(pose, centre, tangent)
    if not np.isfinite(position[0]):
        return None
    return jacobian @ covariance @ jacobian.T
