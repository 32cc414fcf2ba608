"""Both friends' directions and one landmark, calibrated cameras: the relative rotation.

With intrinsics known every tap is a ray. The relative pose is ``X2 = R X1 + t``;
friend 1 sees friend 2 along the unit ``b1`` (frame 1) and friend 2 sees friend 1 along
the unit ``b2`` (frame 2), so ``R b1 = -b2``: that fixes two of the rotation's three degrees
of freedom. The essential matrix ``E = [t]x R`` is, up to scale, ``R [b1]x`` (Hartley &
Zisserman 9.6), and a landmark seen along ``p`` and ``q`` gives ``q . R (b1 x p) = 0``.

That equation says that ``R`` carries the epipolar plane through ``b1`` and ``p`` onto the
epipolar plane through ``b2`` and ``q``. A rotation that takes ``b1`` to ``-b2`` and the
normal ``n1 = b1 x p`` to a multiple of ``n2 = b2 x q`` is fixed by where it sends the
orthonormal frame ``(b1, n1, b1 x n1)``: to ``(-b2, n2, -b2 x n2)`` or to
``(-b2, -n2, b2 x n2)`` (unit normals). So there are exactly two solutions, and they differ
by a half turn about ``b2``; which one has the landmark in front of both cameras is for
the caller to decide.
"""

from __future__ import annotations

import math

import numpy as np

from ..projective import Array

# A ray within this angle (radians) of its baseline fixes no epipolar plane.
_DEGENERATE = 1e-10

Vector = tuple[float, float, float]


def rotations_from_both(b1: Array, b2: Array, ray1: Array, ray2: Array) -> list[Array]:
    """The two rotations ``R`` with ``R b1 = -b2`` and ``ray2 . R (b1 x ray1) = 0``.

    Args:
        b1: (3,) unit direction from friend 1's centre to friend 2's, frame 1.
        b2: (3,) unit direction from friend 2's centre to friend 1's, frame 2.
        ray1: (3,) one landmark's ray in frame 1 (any positive scale).
        ray2: (3,) the same landmark's ray in frame 2.

    Returns:
        Two (3, 3) rotations (orthonormal, det +1), ``R`` and ``Rot(b2, pi) @ R``; empty
        when a ray is parallel to its baseline (the landmark fixes nothing) or zero.
    """
    bx, by, bz = b2.tolist()
    first = _frame(b1.tolist(), ray1.tolist())
    second = _frame([-bx, -by, -bz], ray2.tolist())
    if first is None or second is None:
        return []
    (a1, n1, c1), (a2, n2, c2) = first, second
    # R = sum of outer products (image of each frame-1 axis) (that axis)^T.
    turned = [[a2[i] * a1[j] + n2[i] * n1[j] + c2[i] * c1[j] for j in range(3)] for i in range(3)]
    # Flipping n2 (and so the third axis) is the half turn about b2.
    flipped = [[a2[i] * a1[j] - n2[i] * n1[j] - c2[i] * c1[j] for j in range(3)] for i in range(3)]
    return list(np.array([turned, flipped]))


def _frame(axis: list[float], ray: list[float]) -> tuple[Vector, Vector, Vector] | None:
    """Orthonormal ``(axis, normal of the plane (axis, ray), axis x normal)``, unit vectors.

    None when the axis or the ray is zero, or the ray is (nearly) parallel to the axis.
    """
    ax, ay, az = axis
    rx, ry, rz = ray
    axis_size = math.sqrt(ax * ax + ay * ay + az * az)
    ray_size = math.sqrt(rx * rx + ry * ry + rz * rz)
    if not (axis_size > 0.0 and ray_size > 0.0):
        return None
    ax, ay, az = ax / axis_size, ay / axis_size, az / axis_size
    nx, ny, nz = ay * rz - az * ry, az * rx - ax * rz, ax * ry - ay * rx
    normal_size = math.sqrt(nx * nx + ny * ny + nz * nz)
    if not normal_size > _DEGENERATE * ray_size:
        return None
    nx, ny, nz = nx / normal_size, ny / normal_size, nz / normal_size
    third = (ay * nz - az * ny, az * nx - ax * nz, ax * ny - ay * nx)
    return (ax, ay, az), (nx, ny, nz), third
