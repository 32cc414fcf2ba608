"""Friend 2's direction and three landmarks, calibrated cameras: every relative rotation.

With intrinsics known every tap is a ray. The relative pose is ``X2 = R X1 + t``;
friend 1 sees friend 2 along the unit ``b1`` (frame 1), so ``t`` is parallel to ``-R b1`` and
the essential matrix ``E = [t]x R`` is, up to scale, ``R [b1]x`` (Hartley & Zisserman 9.6).
A landmark seen along ``p`` (frame 1) and ``q`` (frame 2) gives ``q . R (b1 x p) = 0``:
three landmarks, three equations on the three degrees of freedom of ``R``.

Linear part: complete ``b1`` to a right-handed orthonormal basis ``(u, v, b1)`` of frame 1
and write ``m1 = R u``, ``m2 = R v``. Each ``b1 x p`` lies in the plane of ``u`` and ``v``,
so the equations are linear in ``(m1, m2)`` in R^6; three leave a 3-dimensional null space,
``(m1, m2) = x N1 + y N2 + z N3``.

Quadratic part: ``R`` is a rotation exactly when ``|m1| = |m2|`` and ``m1 . m2 = 0`` (then
scale to unit length and ``R = [m1 m2 m1 x m2] [u v b1]^T``). These are two conics in
``(x : y : z)``, which meet in at most four points (Bezout). Each point gives two rotations,
``(m1, m2)`` and ``(-m1, -m2)``, which differ by a half turn about ``b1`` and put friend 2's
view of friend 1 at the same ``b2 = -R b1``: at most eight rotations, in pairs.

The conics are intersected in closed form (Richter-Gebert, Perspectives on Projective
Geometry, ch. 11, splitting a degenerate conic): the pencil ``s C1 + t C2`` has up to three
degenerate members, the real roots of the cubic ``det(s C1 + t C2) = 0``. When there are
real intersections, one of them is a pair of real lines; its adjugate gives the lines'
common point, a rank-one correction splits it, and each line meets another member of the
pencil in at most two points (a quadratic). Rays are scaled to unit length and the null
space is orthonormal, so all the conic coefficients are of order one. Reducing a minimal
pose problem to a linear family intersected with a few quadrics is the pattern of Kukelova
et al.'s E3Q3 (CVPR 2016); PoseLib's relative pose solvers work the same way.
"""

from __future__ import annotations

import math

import numpy as np

from .. import linalg
from ..polynomial import binary_cubic_roots
from ..projective import Array

# The landmark equations have rank below 3 when their smallest singular value is this small
# against the largest: a ray along the baseline, or three landmarks on one epipolar plane.
_DEGENERATE = 1e-10
# A degenerate conic whose line pair is this close (relative) to a double line is refused.
_DOUBLE_LINE = 1e-12
# A quadratic discriminant this far below zero (relative) is a tangency, not a complex pair.
_TANGENT = 1e-13
# A point of the conics' intersection must satisfy both to this (they are of order one).
_ON_BOTH = 1e-9

# The entries (row, column) of a symmetric 3x3 matrix kept in a Symmetric, in order.
_UPPER = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))

Vector = tuple[float, float, float]
# A symmetric 3x3 matrix (a conic) as its six entries (m00, m01, m02, m11, m12, m22).
Symmetric = tuple[float, ...]


def rotations_from_three(b1: Array, rays1: Array, rays2: Array) -> list[Array]:
    """Every rotation ``R`` with ``rays2[i] . R (b1 x rays1[i]) = 0`` for three landmarks.

    Args:
        b1: (3,) direction from friend 1's centre to friend 2's, frame 1 (unit; it is
            normalised anyway).
        rays1: (3, 3) rows are the landmarks' rays in frame 1 (any positive scale).
        rays2: (3, 3) rows are the same landmarks' rays in frame 2.

    Returns:
        (3, 3) rotations (orthonormal, det +1), at most eight, in pairs ``R``,
        ``R @ Rot(b1, pi)`` next to each other. Empty when the input is degenerate (the
        equations leave more than a 3-dimensional null space) or has no real root.
    """
    bx, by, bz = b1.tolist()
    b_size = math.sqrt(bx * bx + by * by + bz * bz)
    if not b_size > 0.0:
        return []
    bx, by, bz = bx / b_size, by / b_size, bz / b_size
    u, v = _basis(bx, by, bz)
    rows = []
    for p, q in zip(rays1.tolist(), rays2.tolist(), strict=True):
        # b1 x p = a u + c v with a = -p . v and c = p . u (the basis is right-handed).
        p_size = math.sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2])
        q_size = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2])
        if not (p_size > 0.0 and q_size > 0.0):
            return []
        a = -(p[0] * v[0] + p[1] * v[1] + p[2] * v[2]) / p_size
        c = (p[0] * u[0] + p[1] * u[1] + p[2] * u[2]) / p_size
        qx, qy, qz = q[0] / q_size, q[1] / q_size, q[2] / q_size
        rows.append([a * qx, a * qy, a * qz, c * qx, c * qy, c * qz])
    _, singular, vt = linalg.svd(np.array(rows))  # acting on (m1, m2) = (R u, R v)
    if not singular[2] > _DEGENERATE * singular[0]:
        return []
    null = vt[3:]  # (3, 6), orthonormal rows N_k = (top_k, bottom_k)
    c1, c2 = _conics(null)
    points = _conic_intersections(c1, c2)
    if not points:
        return []
    null_rows = null.tolist()
    rotations = [_rotation_pair(w, null_rows, u, v, (bx, by, bz)) for w in points]
    return list(np.array(rotations).reshape(-1, 3, 3))


def _conics(null: Array) -> tuple[Symmetric, Symmetric]:
    """``|m1|^2 - |m2|^2`` and ``2 m1 . m2`` as conics in ``w`` for ``(m1, m2) = w . null``."""
    # Gram matrix of top_0, bottom_0, top_1, bottom_1, top_2, bottom_2.
    flat = null.reshape(6, 3)
    g = (flat @ flat.T).tolist()
    first = tuple(g[2 * i][2 * j] - g[2 * i + 1][2 * j + 1] for i, j in _UPPER)
    second = tuple(g[2 * i][2 * j + 1] + g[2 * i + 1][2 * j] for i, j in _UPPER)
    return first, second


def _basis(x: float, y: float, z: float) -> tuple[Vector, Vector]:
    """``u, v`` with ``(u, v, b1)`` a right-handed orthonormal basis, for unit ``b1``."""
    # u = b1 x e for the axis e least aligned with b1, so that |u| >= sqrt(2/3).
    if abs(x) <= abs(y) and abs(x) <= abs(z):
        u = _unit((0.0, z, -y))
    elif abs(y) <= abs(z):
        u = _unit((-z, 0.0, x))
    else:
        u = _unit((y, -x, 0.0))
    return u, _cross((x, y, z), u)


def _conic_intersections(c1: Symmetric, c2: Symmetric) -> list[Vector]:
    """Unit real points ``w`` (at most four) with ``w^T c1 w = w^T c2 w = 0``."""
    candidates = []
    for s, t in _degenerate_members(c1, c2):
        a, b, c, d, e, f = member = _combine(s, c1, t, c2)
        # Minus the trace of the adjugate: > 0 for a pair of real lines, < 0 for a
        # conjugate complex pair, 0 for a double line.
        spread = b * b + c * c + e * e - d * f - a * f - a * d
        size = max(abs(a), abs(b), abs(c), abs(d), abs(e), abs(f))
        if spread > _DOUBLE_LINE * size * size:
            candidates.append((spread / (size * size), member, _combine(-t, c1, s, c2)))
    # The best-split real line pair; should rounding have faked a root, the next one.
    candidates.sort(key=lambda found: -found[0])
    for _, member, other in candidates:
        points = _lines_meet(member, other)
        if all(
            abs(_form(c1, w, w)) <= _ON_BOTH and abs(_form(c2, w, w)) <= _ON_BOTH for w in points
        ):
            return points
    return []


def _degenerate_members(c1: Symmetric, c2: Symmetric) -> list[tuple[float, float]]:
    """Unit (s, t) with ``det(s c1 + t c2) = 0``: the real roots of a homogeneous cubic."""
    k0, k3 = _det(c1), _det(c2)
    plus, minus = _det(_combine(1.0, c1, 1.0, c2)), _det(_combine(1.0, c1, -1.0, c2))
    # det(s c1 + t c2) = k0 s^3 + k1 s^2 t + k2 s t^2 + k3 t^3
    return binary_cubic_roots(k0, 0.5 * (plus - minus) - k3, 0.5 * (plus + minus) - k0, k3)


def _lines_meet(member: Symmetric, other: Symmetric) -> list[Vector]:
    """Split a degenerate conic into its two real lines and meet each with ``other``.

    For ``D = l m^T + m l^T`` the adjugate is ``-(l x m)(l x m)^T``: a column scaled by the
    root of minus its diagonal entry is ``p = +-(l x m)``, the lines' common point, and
    ``D + [p]x`` has rank one, ``2 m l^T`` or ``2 l m^T``; the row and the column of its
    largest entry are the two lines. A point on a line is ``alpha p + beta (line x p)``.
    """
    a, b, c, d, e, f = member
    adjugate = _adjugate(member)
    diagonal = (adjugate[0], adjugate[3], adjugate[5])
    pivot = min(range(3), key=diagonal.__getitem__)
    if not diagonal[pivot] < 0.0:
        return []
    column = ((0, 1, 2), (1, 3, 4), (2, 4, 5))[pivot]
    root = math.sqrt(-diagonal[pivot])
    px, py, pz = (adjugate[k] / root for k in column)
    rank_one = (
        (a, b - pz, c + py),
        (b + pz, d, e - px),
        (c - py, e + px, f),
    )
    sizes = [abs(value) for row in rank_one for value in row]
    i, j = divmod(sizes.index(max(sizes)), 3)
    lines = (rank_one[i], (rank_one[0][j], rank_one[1][j], rank_one[2][j]))
    centre = _unit((px, py, pz))
    on_centre = _form(other, centre, centre)
    points = []
    for line in lines:
        along = _unit(_cross(line, centre))
        quadratic = (on_centre, _form(other, centre, along), _form(other, along, along))
        for alpha, beta in _homogeneous_quadratic(*quadratic):
            points.append(
                _unit(tuple(alpha * x + beta * y for x, y in zip(centre, along, strict=True)))
            )
    return points


def _homogeneous_quadratic(a: float, b: float, c: float) -> list[tuple[float, float]]:
    """Real roots (alpha, beta), up to scale, of ``a alpha^2 + 2 b alpha beta + c beta^2``."""
    scale = b * b + abs(a * c)
    if scale == 0.0:
        return []  # the whole line lies on the conic: not a finite set of points
    discriminant = b * b - a * c
    if discriminant < -_TANGENT * scale:
        return []
    root = math.sqrt(max(discriminant, 0.0))
    # No cancellation: q has the sign of -b, and the roots are (q : a) and (c : q).
    q = -(b + math.copysign(root, b))
    size = math.sqrt(scale)
    return [pair for pair in ((q, a), (c, q)) if math.hypot(*pair) > 1e-12 * size]


def _rotation_pair(
    w: Vector, null: list[list[float]], u: Vector, v: Vector, b1: Vector
) -> list[list[list[float]]]:
    """``R = [m1 m2 m1 x m2] [u v b1]^T`` for ``(m1, m2) = w . null``, and ``R @ Rot(b1, pi)``."""
    (a0, a1, a2, a3, a4, a5), (b0, b1_, b2, b3, b4, b5), (c0, c1, c2, c3, c4, c5) = null
    x, y, z = w
    m1 = _unit((x * a0 + y * b0 + z * c0, x * a1 + y * b1_ + z * c1, x * a2 + y * b2 + z * c2))
    m2 = (x * a3 + y * b3 + z * c3, x * a4 + y * b4 + z * c4, x * a5 + y * b5 + z * c5)
    along = m1[0] * m2[0] + m1[1] * m2[1] + m1[2] * m2[2]  # ~0: removes rounding only
    m2 = _unit((m2[0] - along * m1[0], m2[1] - along * m1[1], m2[2] - along * m1[2]))
    m3 = _cross(m1, m2)
    turned = [
        [
            p * u[0] + q * v[0] + r * b1[0],
            p * u[1] + q * v[1] + r * b1[1],
            p * u[2] + q * v[2] + r * b1[2],
        ]
        for p, q, r in zip(m1, m2, m3, strict=True)
    ]
    # R @ (2 b1 b1^T - I) = 2 (R b1) b1^T - R, and R b1 = m3.
    flipped = [
        [2.0 * r * b1[0] - row[0], 2.0 * r * b1[1] - row[1], 2.0 * r * b1[2] - row[2]]
        for r, row in zip(m3, turned, strict=True)
    ]
    return [turned, flipped]


def _combine(s: float, c1: Symmetric, t: float, c2: Symmetric) -> Symmetric:
    """``s c1 + t c2``."""
    a1, b1, c1_, d1, e1, f1 = c1
    a2, b2, c2_, d2, e2, f2 = c2
    return (
        s * a1 + t * a2,
        s * b1 + t * b2,
        s * c1_ + t * c2_,
        s * d1 + t * d2,
        s * e1 + t * e2,
        s * f1 + t * f2,
    )


def _det(m: Symmetric) -> float:
    a, b, c, d, e, f = m
    return a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d)


def _adjugate(m: Symmetric) -> Symmetric:
    """The adjugate (symmetric for a symmetric matrix)."""
    a, b, c, d, e, f = m
    return (
        d * f - e * e,
        c * e - b * f,
        b * e - c * d,
        a * f - c * c,
        b * c - a * e,
        a * d - b * b,
    )


def _form(m: Symmetric, x: Vector, y: Vector) -> float:
    """The bilinear form ``x^T m y``."""
    a, b, c, d, e, f = m
    return (
        x[0] * (a * y[0] + b * y[1] + c * y[2])
        + x[1] * (b * y[0] + d * y[1] + e * y[2])
        + x[2] * (c * y[0] + e * y[1] + f * y[2])
    )


def _cross(a: Vector, b: Vector) -> Vector:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _unit(a: tuple[float, ...]) -> Vector:
    scale = 1.0 / math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    return (a[0] * scale, a[1] * scale, a[2] * scale)
