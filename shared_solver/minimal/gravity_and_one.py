"""Friend 2's direction, both photos' gravity and one landmark, calibrated cameras: the
relative rotation.

The relative pose is ``X2 = R X1 + t``. Each phone measured which way is down in its own
frame, ``g1`` and ``g2``, and down is the same direction for both: ``R g1 = g2``. Write
``R = Q2^T Rz(psi) Q1`` with ``Q_i`` any rotation taking ``g_i`` to the z axis: every
such ``R`` carries ``g1`` to ``g2``, and the one unknown left is ``psi``, the turn about
the vertical between the two phones.

Friend 1 sees friend 2 along ``b1`` (frame 1), so the essential matrix is, up to scale,
``R [b1]x`` (as in :mod:`.both_and_one`), and a landmark seen along ``p`` and ``q`` gives
``q . R (b1 x p) = 0``. With ``a = Q2 q`` and ``n = Q1 (b1 x p)`` that is

    cos(psi) (a_x n_x + a_y n_y) + sin(psi) (a_y n_x - a_x n_y) + a_z n_z = 0,

``A cos(psi) + B sin(psi) + C = 0``: two turns when ``|C| < sqrt(A^2 + B^2)``, one when
equal, none beyond. Which one puts the landmark in front of both cameras is for the caller.

With no landmark ``psi`` stays free: :func:`rotation_about_vertical` gives the rotation of
any turn, the curve on which friend 1 appears in photo 2. Both phones' compass headings
measure it: :func:`turn_from_headings`.
"""

from __future__ import annotations

import math

import numpy as np

from ..projective import Array

# Horizontal parts smaller than this (relative) fix no turn: the landmark's epipolar plane
# is level or its ray in photo 2 is vertical, and every turn fits it or none does.
_DEGENERATE = 1e-10


def level_frame(gravity: Array) -> Array:
    """(3, 3) a rotation ``Q`` with ``Q g = (0, 0, 1)`` for a unit ``g`` (3,): its rows are an
    orthonormal basis whose third vector is ``g``. Which basis (a turn about ``g``) does not
    matter: the turn about the vertical absorbs it."""
    x, y, z = np.asarray(gravity, dtype=np.float64).tolist()
    size = math.sqrt(x * x + y * y + z * z)
    x, y, z = x / size, y / size, z / size
    # first = helper x g, with helper (1, 0, 0), or (0, 1, 0) when g is near the x axis.
    fx, fy, fz = (0.0, -z, y) if abs(x) < 0.9 else (z, 0.0, -x)
    size = math.sqrt(fx * fx + fy * fy + fz * fz)
    fx, fy, fz = fx / size, fy / size, fz / size
    second = (y * fz - z * fy, z * fx - x * fz, x * fy - y * fx)  # g x first
    return np.array([[fx, fy, fz], second, [x, y, z]])


def rotation_about_vertical(gravity1: Array, gravity2: Array, turn: float | Array) -> Array:
    """``R = Q2^T Rz(psi) Q1`` for a turn ``psi`` (radians; scalar or (K,)): (3, 3) or
    (K, 3, 3) rotations with ``R g1 = g2``."""
    psi = np.asarray(turn, dtype=np.float64)
    c, s = np.cos(psi), np.sin(psi)
    rz = np.zeros((*psi.shape, 3, 3))
    rz[..., 0, 0], rz[..., 0, 1], rz[..., 1, 0], rz[..., 1, 1] = c, -s, s, c
    rz[..., 2, 2] = 1.0
    result: Array = level_frame(gravity2).T @ rz @ level_frame(gravity1)
    return result


def turns_from_gravity(
    b1: Array, gravity1: Array, gravity2: Array, ray1: Array, ray2: Array
) -> list[float]:
    """Every turn ``psi`` (radians, in (-pi, pi]) with ``ray2 . R(psi) (b1 x ray1) = 0``.

    Args:
        b1: (3,) direction from friend 1's centre to friend 2's, frame 1 (any length).
        gravity1, gravity2: (3,) unit down directions in frames 1 and 2.
        ray1: (3,) one landmark's ray in frame 1 (any positive scale).
        ray2: (3,) the same landmark's ray in frame 2.

    Returns:
        Zero, one or two turns; empty when the landmark fixes none (module docstring).
    """
    # In plain floats: this runs for every start of every fit with gravity.
    bx, by, bz = np.asarray(b1, dtype=np.float64).tolist()
    px, py, pz = np.asarray(ray1, dtype=np.float64).tolist()
    normal = (by * pz - bz * py, bz * px - bx * pz, bx * py - by * px)  # b1 x ray1
    ax, ay, az = (level_frame(gravity2) @ np.asarray(ray2, dtype=np.float64)).tolist()
    nx, ny, nz = (level_frame(gravity1) @ normal).tolist()
    big_a, big_b, big_c = ax * nx + ay * ny, ay * nx - ax * ny, az * nz
    radius = math.hypot(big_a, big_b)
    scale = math.sqrt((ax * ax + ay * ay + az * az) * (nx * nx + ny * ny + nz * nz))
    if not radius > _DEGENERATE * scale:
        return []
    cosine = -big_c / radius
    if abs(cosine) > 1.0:
        return []
    centre, half = math.atan2(big_b, big_a), math.acos(cosine)
    turns = [centre - half] if half == 0.0 else [centre - half, centre + half]
    return [math.remainder(turn, 2.0 * math.pi) for turn in turns]


def rotations_from_gravity(
    b1: Array, gravity1: Array, gravity2: Array, ray1: Array, ray2: Array
) -> list[Array]:
    """The rotations (3, 3) of :func:`turns_from_gravity`'s turns, each with ``R g1 = g2``."""
    return [
        rotation_about_vertical(gravity1, gravity2, turn)
        for turn in turns_from_gravity(b1, gravity1, gravity2, ray1, ray2)
    ]


def north(gravity: Array, heading: float) -> Array:
    """(3,) north in a camera's frame: the horizontal unit vector that the lens axis's
    horizontal direction is ``heading`` radians clockwise from, seen from above.

    Clockwise seen from above is a right-handed turn about down (``gravity``, unit (3,)), so
    north is the lens axis's horizontal direction ``l`` turned back by the heading:
    ``l cos(h) - (g x l) sin(h)`` (Rodrigues, ``g . l = 0``). A lens pointing straight up or
    down has no horizontal direction: NaN then.
    """
    # In plain floats, as turns_from_gravity: numpy's cross product costs more than this.
    gx, gy, gz = np.asarray(gravity, dtype=np.float64).tolist()
    lx, ly, lz = -gz * gx, -gz * gy, 1.0 - gz * gz  # the lens axis z, made horizontal
    size = math.sqrt(lx * lx + ly * ly + lz * lz)
    if not size > _DEGENERATE:
        return np.full(3, np.nan)
    lx, ly, lz = lx / size, ly / size, lz / size
    c, s = math.cos(heading), math.sin(heading)
    across = (gy * lz - gz * ly, gz * lx - gx * lz, gx * ly - gy * lx)  # g x l
    return np.array([lx * c - across[0] * s, ly * c - across[1] * s, lz * c - across[2] * s])


def turn_from_headings(gravity1: Array, gravity2: Array, heading1: float, heading2: float) -> float:
    """The turn ``psi`` (radians, in (-pi, pi]) of :func:`rotation_about_vertical` that
    carries photo 1's north onto photo 2's, ``R(psi) n1 = n2``: what the two phones'
    compass headings (radians, clockwise from north) say of it."""
    a1 = level_frame(gravity1) @ north(gravity1, heading1)
    a2 = level_frame(gravity2) @ north(gravity2, heading2)
    # Both are horizontal, so z is 0 in the level frames and Rz(psi) turns a1 onto a2.
    return math.remainder(math.atan2(a2[1], a2[0]) - math.atan2(a1[1], a1[0]), 2.0 * math.pi)
