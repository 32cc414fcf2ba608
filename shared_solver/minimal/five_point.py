"""Five landmarks and the buddy's position: where the seeker stands (paper 3.2).

Two routes to the same point, each a test oracle for the other:

* ``cremona``: the paper's closed form. The conics through landmarks {i,j,k,l} and
  {i,j,k,m} (each through ``e2``) share ``q_i, q_j, q_k``. In the projective frame where
  those three are the basis points a conic through them has no square terms, and the
  reciprocal Cremona map ``(x, y, z) -> (yz, zx, xy)`` turns it into a line; the two lines
  meet in the image of ``e2``. Plain float arithmetic, no allocation.
* ``linear``: the null space of the linear system of :mod:`.five_point_linear`.

Because the problem is minimal, both give the same ``e2`` on exact and on noisy taps.
"""

from __future__ import annotations

import math
from itertools import chain, combinations
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from .. import validation, words
from ..errors import ErrorCode, SolverError
from ..projective import Array, canonical, left_epipole
from .five_point_linear import fundamental_with_epipole

FiveMethod = Literal["cremona", "linear"]

_PAIRS = tuple(combinations(range(5), 2))
Frame = tuple[tuple[int, int, int], tuple[int, int]]  # (basis landmarks, the other two)


def _frames() -> tuple[Frame, ...]:
    frames = []
    for i, j, k in combinations(range(5), 3):
        l, m = (other for other in range(5) if other not in (i, j, k))  # noqa: E741
        frames.append(((i, j, k), (l, m)))
    return tuple(frames)


_TRIPLES = _frames()
# A bracket or triangle area this small relative to the image extent squared means the input
# may sit on a degeneracy: the full validation decides.
_NEAR_ZERO = validation.EXACT_TOLERANCE
# Below this a line intersection or a reciprocal is a removable singularity of the chosen
# frame, not an answer: another choice of basis landmarks is tried.
_SINGULAR = 1e-10


def epipole_from_five(
    e1: ArrayLike, pts1: ArrayLike, pts2: ArrayLike, method: FiveMethod = "cremona"
) -> Array:
    """Where the seeker stands in photo 2, from 5 landmarks and the buddy's tap (paper 3.2).

    Args:
        e1: (2,) pixel or (3,) homogeneous position of the buddy in photo 1 (epipole 1).
        pts1: (5, 2) landmarks in photo 1, pixels.
        pts2: (5, 2) the same landmarks in photo 2, pixels.
        method: ``"cremona"`` (the paper's reciprocal-Cremona closed form) or ``"linear"``
            (null space of the 5x6 system left after eliminating ``F e1 = 0``).

    Returns:
        (3,) homogeneous ``e2``, unit norm, ``w >= 0``; ``w == 0`` means at infinity.

    Raises:
        SolverError: invalid or degenerate input.
    """
    if method == "cremona":
        floats = _plain_floats(e1, pts1, pts2)
        if floats is not None:
            e2 = cremona_epipole(*floats)
            if e2 is not None:
                return canonical(e2)
        # Malformed or near-degenerate: the full checks say exactly what is wrong.
        e1h, p, q = _checked_five(e1, pts1, pts2)
        e2 = cremona_epipole(e1h.tolist(), p.tolist(), q.tolist(), checked=True)
        if e2 is None:
            raise SolverError(ErrorCode.DEGENERATE_CONFIGURATION, words.SEEKER_UNDETERMINED)
        return canonical(e2)
    if method == "linear":
        e1h, p, q = _checked_five(e1, pts1, pts2)
        return canonical(left_epipole(fundamental_with_epipole(e1h, p, q)))
    raise SolverError(ErrorCode.INVALID_PARAMETER, words.FIVE_METHOD)


Floats = list[float]


def _checked_five(e1: ArrayLike, pts1: ArrayLike, pts2: ArrayLike) -> tuple[Array, Array, Array]:
    e1h = validation.point(e1, "e1")
    p, q = validation.landmark_pairs(pts1, pts2, minimum=5, maximum=5, epipole1=e1h)
    return e1h, p, q


def _plain_floats(
    e1: ArrayLike, pts1: ArrayLike, pts2: ArrayLike
) -> tuple[Floats, list[Floats], list[Floats]] | None:
    """Well-formed finite input as Python floats, or None for the full checks to explain."""
    try:
        e, p, q = (np.asarray(v, dtype=np.float64) for v in (e1, pts1, pts2))
    except (TypeError, ValueError):
        return None
    if e.shape not in ((2,), (3,)) or p.shape != (5, 2) or q.shape != (5, 2):
        return None
    el, pl, ql = e.tolist(), p.tolist(), q.tolist()
    if len(el) == 2:
        el.append(1.0)
    if not all(map(math.isfinite, chain(el, *pl, *ql))) or not any(el):
        return None
    return el, pl, ql


def cremona_epipole(
    e1: Floats, p: list[Floats], q: list[Floats], *, checked: bool = False
) -> tuple[float, float, float] | None:
    """The paper's closed form in plain floats: e1 (3,), p and q (5, 2) -> homogeneous e2.

    Returns None when the input sits on a degeneracy (a landmark on the buddy, repeated or
    collinear landmarks, two landmarks on one epipolar line) unless ``checked`` says the
    full validation has already accepted it; then every frame is tried.
    """
    pencil = _pencil(e1, p)
    area2 = _twice_areas(q)
    if not checked and _may_be_degenerate(p, q, e1[2], pencil, area2):
        return None
    best = max(range(len(_TRIPLES)), key=area2.__getitem__)
    # The best-spread triple of photo-2 landmarks makes the best-conditioned frame; the others
    # are only needed when that frame hits a removable singularity.
    for choice in (best, *sorted(range(len(_TRIPLES)), key=lambda c: -area2[c])):
        e2, meet, lines, reciprocal = _in_frame(pencil, q, *_TRIPLES[choice])
        if meet > _SINGULAR**2 * lines and reciprocal > _SINGULAR**2 * meet * meet:
            return e2
    return None


def cremona_batch(e1: Array, p: Array, q: Array) -> Array:
    """The closed form for K problems at once: e1 (K, 3), p and q (K, 5, 2) -> e2 (K, 3).

    Used for Monte Carlo and for hypotheses over subsets of landmarks; rows whose best frame
    is singular come back as NaN (callers treat them as no answer).
    """
    areas = np.stack(_twice_areas(q.transpose(1, 2, 0)), axis=1)
    order = np.array([triple + extras for triple, extras in _TRIPLES])[np.argmax(areas, axis=1)]
    rows = np.arange(len(q))[:, None]
    p_cols, q_cols = p[rows, order].transpose(1, 2, 0), q[rows, order].transpose(1, 2, 0)
    e2, meet, lines, reciprocal = _in_frame(_pencil(e1.T, p_cols), q_cols, (0, 1, 2), (3, 4))
    result = np.stack(e2, axis=1)
    singular = (meet <= _SINGULAR**2 * lines) | (reciprocal <= _SINGULAR**2 * meet * meet)
    result[singular] = np.nan
    return result


# The closed form below runs unchanged on Python floats (one problem, fast) and on numpy
# arrays of shape (K,) (K problems): it uses nothing but arithmetic.


def _pencil(e1: Any, p: Any) -> list[list[Any]]:
    """|e1 p_a p_b| for all pairs: the brackets of the epipolar lines through e1."""
    ex, ey, ew = e1
    pencil: list[list[Any]] = [[0.0] * 5 for _ in range(5)]
    for a, b in _PAIRS:
        (ax, ay), (bx, by) = p[a], p[b]
        pencil[a][b] = bracket = ex * (ay - by) + ey * (bx - ax) + ew * (ax * by - ay * bx)
        pencil[b][a] = -bracket
    return pencil


def _twice_areas(points: Any) -> list[Any]:
    """Twice the area of each triangle of ``_TRIPLES`` (zero: three collinear landmarks)."""
    return [
        abs(
            (points[j][0] - points[i][0]) * (points[k][1] - points[i][1])
            - (points[j][1] - points[i][1]) * (points[k][0] - points[i][0])
        )
        for (i, j, k), _ in _TRIPLES
    ]


def _in_frame(pencil: Any, q: Any, basis: tuple[int, int, int], extras: tuple[int, int]) -> Any:
    """e2 with q_i, q_j, q_k as the projective basis, and the frame's conditioning.

    Returns ``((x, y, w), meet, lines, reciprocal)``: the frame is singular when ``meet``
    (squared norm of the meet of the two reciprocal lines) is tiny against ``lines`` (product
    of their squared norms), or ``reciprocal`` against ``meet**2``.
    """
    i, j, k = basis
    (ix, iy), (jx, jy), (kx, ky) = q[i], q[j], q[k]
    # Rows of adj([q_i q_j q_k]): coordinates in the frame where q_i, q_j, q_k are the basis.
    r1x, r1y, r1w = jy - ky, kx - jx, jx * ky - jy * kx
    r2x, r2y, r2w = ky - iy, ix - kx, kx * iy - ky * ix
    r3x, r3y, r3w = iy - jy, jx - ix, ix * jy - iy * jx
    lines = []
    for extra in extras:
        x, y = q[extra]
        # The conic -A c xy + B b xz + (A - B) a yz = 0 through the basis points, with
        # A = [ij][k extra], B = [ik][j extra] and A - B = -[i extra][jk] (Pluecker), maps
        # under the reciprocal (x, y, z) -> (yz, zx, xy) to this line:
        lines.append(
            (
                -pencil[i][extra] * pencil[j][k] * (r1x * x + r1y * y + r1w),
                pencil[i][k] * pencil[j][extra] * (r2x * x + r2y * y + r2w),
                -pencil[i][j] * pencil[k][extra] * (r3x * x + r3y * y + r3w),
            )
        )
    (u1, u2, u3), (v1, v2, v3) = lines
    x, y, z = u2 * v3 - u3 * v2, u3 * v1 - u1 * v3, u1 * v2 - u2 * v1
    s, t, w = y * z, z * x, x * y  # the reciprocal again: back to the frame of the conics
    e2 = (s * ix + t * jx + w * kx, s * iy + t * jy + w * ky, s + t + w)
    meet = x * x + y * y + z * z
    norms = (u1 * u1 + u2 * u2 + u3 * u3) * (v1 * v1 + v2 * v2 + v3 * v3)
    return e2, meet, norms, s * s + t * t + w * w


def _may_be_degenerate(
    p: list[Floats], q: list[Floats], ew: float, pencil: list[Floats], area2: Floats
) -> bool:
    """Cheap trigger for the full validation: some bracket or triangle is (near) zero."""
    size1, size2 = _extent(p), _extent(q)
    tol1, tol2 = _NEAR_ZERO * size1 * size1, _NEAR_ZERO * size2 * size2
    if min(area2) <= tol2 or min(abs(pencil[a][b]) for a, b in _PAIRS) <= tol1 * abs(ew):
        return True
    # p_0 != p_1 (their bracket is not zero), so all are collinear iff each p_k is on p_0 p_1.
    (x0, y0), (x1, y1) = p[0], p[1]
    return max(abs((x1 - x0) * (y - y0) - (y1 - y0) * (x - x0)) for x, y in p[2:]) <= tol1


def _extent(points: list[Floats]) -> float:
    """Bounding-box diagonal of the points, at least 1 (px)."""
    xs, ys = [x for x, _ in points], [y for _, y in points]
    return max(math.hypot(max(xs) - min(xs), max(ys) - min(ys)), 1.0)
