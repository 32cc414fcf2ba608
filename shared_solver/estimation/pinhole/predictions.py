"""What a pose says the photos show: where each friend appears, and F, with their derivatives
along the seven parameters (:mod:`.pose`).

Friend 2 appears in photo 1 at ``pi(K1 b1)``, friend 1 in photo 2 at ``pi(-K2 R b1)``, and
``F = K2^-T R [b1]x K1^-1`` (Hartley & Zisserman 9.6). The one-pose functions run at every
iteration of every fit, so they work in plain floats where numpy's per-call cost would
dominate; the ``*_positions`` functions take a batch of K poses, without derivatives.
"""

from __future__ import annotations

import math

import numpy as np

from ...projective import Array
from .pose import FOCAL2, FRIEND2, PARAMETERS, ROTATION, Poses, skews

# Below this |w| of the direction friend 1 is seen in, they are at infinity in photo 2.
_AT_INFINITY = 1e-12


def friend1_pixel(pose: Poses, centre: tuple[float, float], tangent: Array) -> tuple[Array, Array]:
    """Friend 1 in photo 2 at one pose, ``pi(-K2 R b1)``: pixel (2,) and Jacobian (2, 7),
    NaN when friend 1 is at infinity (in friend 2's image plane); ``tangent``: (3, 2)
    tangent basis of friend 2's direction."""
    log_f1, log_f2 = pose.log_focals[0].tolist()
    f2, ratio = math.exp(log_f2), math.exp(pose.reference - log_f1)
    ux, uy, uz = pose.friend2[0].tolist()
    (ax, bx), (ay, by), (az, bz) = tangent.tolist()
    # b1, its steps along the tangent basis and d b1 / d ln f1, as columns; v = -R b1.
    columns = [
        [ratio * ux, ratio * ax, ratio * bx, -ratio * ux],
        [ratio * uy, ratio * ay, ratio * by, -ratio * uy],
        [uz, az, bz, 0.0],
    ]
    moved = -pose.rotation[0] @ np.array(columns)  # v, then its derivatives
    x, y, z = moved[:, 0].tolist()
    if abs(z) <= _AT_INFINITY * math.sqrt(x * x + y * y + z * z):
        return np.full(2, np.nan), np.full((2, PARAMETERS), np.nan)
    d_project = np.array([[f2 / z, 0.0, -f2 * x / (z * z)], [0.0, f2 / z, -f2 * y / (z * z)]])
    jacobian = np.empty((2, PARAMETERS))
    jacobian[:, ROTATION] = d_project @ np.array(_skew(-x, -y, -z))  # dv = dw x v
    jacobian[:, 3:6] = d_project @ moved[:, 1:]  # friend 2's steps, then ln f1
    jacobian[:, FOCAL2] = f2 * x / z, f2 * y / z
    return np.array([centre[0] + f2 * x / z, centre[1] + f2 * y / z]), jacobian


def friend1_positions(poses: Poses, centre: Array) -> Array:
    """(K, 2) friend 1 in photo 2, ``pi(-K2 R b1)``, without derivatives (NaN at infinity,
    as :func:`friend1_pixel`)."""
    f2 = np.exp(poses.log_focals[:, 1])
    v = -np.einsum("kij,kj->ki", poses.rotation, poses.baseline)
    v[np.abs(v[:, 2]) <= _AT_INFINITY * np.sqrt(np.einsum("ki,ki->k", v, v)), 2] = np.nan
    return centre + f2[:, None] * v[:, :2] / v[:, 2:]


def friend2_positions(poses: Poses, centre: Array) -> Array:
    """(K, 2) friend 2 in photo 1, ``pi(K1 b1) = pi(K_reference u)``, without derivatives."""
    u = poses.friend2
    return centre + math.exp(poses.reference) * u[:, :2] / u[:, 2:]


def friend2_pixel(pose: Poses, centre: tuple[float, float], tangent: Array) -> tuple[Array, Array]:
    """Friend 2 in photo 1 at one pose, ``pi(K1 b1) = pi(K_reference u)``: pixel (2,) and
    Jacobian (2, 7), which depends on friend 2's direction alone."""
    reference = math.exp(pose.reference)
    x, y, z = pose.friend2[0].tolist()
    scale = reference / z
    d_project = np.array([[scale, 0.0, -scale * x / z], [0.0, scale, -scale * y / z]])
    jacobian = np.zeros((2, PARAMETERS))
    jacobian[:, FRIEND2] = d_project @ tangent
    return np.array([centre[0] + scale * x, centre[1] + scale * y]), jacobian


def fundamental_stack(
    pose: Poses, centres: tuple[tuple[float, float], tuple[float, float]], tangent: Array
) -> Array:
    """(8, 3, 3) F in pixels at one pose (not normalised), then its derivatives along the 7
    tangent parameters (rotation, friend 2's direction, log focal lengths).

    ``centres``: the principal points of photo 1 and 2, px; ``tangent``: (3, 2) tangent
    basis of friend 2's direction.
    """
    log_f1, log_f2 = pose.log_focals[0].tolist()
    f1, f2 = math.exp(log_f1), math.exp(log_f2)
    (x1, y1), (x2, y2) = centres
    inverse1 = np.array([[1.0 / f1, 0.0, -x1 / f1], [0.0, 1.0 / f1, -y1 / f1], [0.0, 0.0, 1.0]])
    inverse2_t = np.array([[1.0 / f2, 0.0, 0.0], [0.0, 1.0 / f2, 0.0], [-x2 / f2, -y2 / f2, 1.0]])
    # b1 = diag(r, r, 1) u, its steps along the tangent basis, and d b1 / d ln f1, as one
    # call for all four cross-product matrices (plain floats: these are 3-vectors).
    ratio = math.exp(pose.reference - log_f1)
    ux, uy, uz = pose.friend2[0].tolist()
    (ax, bx), (ay, by), (az, bz) = tangent.tolist()
    skew_matrices = np.array(
        [
            _skew(ratio * ux, ratio * uy, uz),
            _skew(ratio * ax, ratio * ay, az),
            _skew(ratio * bx, ratio * by, bz),
            _skew(-ratio * ux, -ratio * uy, 0.0),
        ]
    )
    moved = pose.rotation[0] @ skew_matrices  # R [b1]x = E, then R [.]x of b1's three derivatives
    essential = moved[0]
    # K2^-T M K1^-1 for each M below is F, then dF along each parameter. d K1^-1 / d ln f1
    # is -P K1^-1 and d K2^-T / d ln f2 is -K2^-T P, with P = diag(1, 1, 0); ln f1 also
    # moves b1 (friend 2's pixel stays).
    middle = np.empty((8, 3, 3))
    middle[0] = essential
    middle[1:4] = _BASIS_SKEWS @ essential  # d exp([w]x) R = [e_k]x R
    middle[4:7] = moved[1:4]
    middle[6, :, :2] -= essential[:, :2]  # - E P
    middle[7, :2], middle[7, 2] = -essential[:2], 0.0  # - P E
    return inverse2_t @ middle @ inverse1


def _skew(x: float, y: float, z: float) -> list[list[float]]:
    """The cross-product matrix of one vector, as nested lists (for one ``np.array`` call)."""
    return [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]]


_BASIS_SKEWS = skews(np.eye(3))  # [e_k]x
