"""Five landmarks and friend 2's position: where friend 1 stands (paper 3.2).

Two routes to the same point, each a test oracle for the other:

* ``cremona``: the paper's closed form. The conics through landmarks {i,j,k,l} and
  {i,j,k,m} (each through ``e2``) share ``q_i, q_j, q_k``. In the projective frame where
  those three are the basis points a conic through them has no square terms, and the
  reciprocal Cremona map ``(x, y, z) -> (yz, zx, xy)`` turns it into a line; the two lines
  meet in the image of ``e2``. Plain float arithmetic, no allocation.
* ``linear``: the null space of the linear system of :mod:`.five_point_linear`.

Because the problem is minimal, both give the same ``e2`` on exact and on noisy taps.

The closed form costs less than validating its input with numpy, so well-spread input skips
:mod:`..validation`: a cheap test on numbers the closed form needs anyway (brackets and
triangle areas) fires on everything the full checks would refuse, and only then do they run.
"""

from __future__ import annotations

import math
from itertools import combinations
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from .. import validation
from ..errors import Reason
from ..projective import Array, canonical, left_epipole
from ..refusal import SolverError
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
# The full validation's tolerance, relative to a photo's spread: a bracket or triangle area
# near the bounds it implies (see _may_be_degenerate) may sit on a degeneracy.
_NEAR_ZERO = validation.EXACT_TOLERANCE
# Those bounds are exact; this factor keeps the cheap test on the safe side of rounding.
_MARGIN = 2.0
_COLLINEAR = 4.0 * _MARGIN * _NEAR_ZERO  # twice-area bound over spread squared
# Below this a line intersection or a reciprocal is a removable singularity of the chosen
# frame, not an answer: another choice of basis landmarks is tried.
_SINGULAR = 1e-10


def epipole_from_five(
    e1: ArrayLike, pts1: ArrayLike, pts2: ArrayLike, method: FiveMethod = "cremona"
) -> Array:
    """Where friend 1 stands in photo 2, from 5 landmarks and friend 2's tap (paper 3.2).

    Args:
        e1: (2,) pixel or (3,) homogeneous position of friend 2 in photo 1 (epipole 1).
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
                return _canonical(*e2)
        # Malformed or near-degenerate: the full checks say exactly what is wrong.
        e1h, p, q = _checked_five(e1, pts1, pts2)
        e2 = cremona_epipole(e1h.tolist(), p.T.tolist(), q.T.tolist(), checked=True)
        if e2 is None:
            raise SolverError(Reason.FRIEND_UNDETERMINED)
        return _canonical(*e2)
    if method == "linear":
        e1h, p, q = _checked_five(e1, pts1, pts2)
        return canonical(left_epipole(fundamental_with_epipole(e1h, p, q)))
    raise SolverError(Reason.FIVE_METHOD)


Floats = list[float]
Columns = list[Floats]  # [xs, ys] of the 5 landmarks of one photo


def _checked_five(e1: ArrayLike, pts1: ArrayLike, pts2: ArrayLike) -> tuple[Array, Array, Array]:
    e1h = validation.point(e1, "e1")
    p, q = validation.landmark_pairs(pts1, pts2, minimum=5, maximum=5, epipole1=e1h)
    return e1h, p, q


def _plain_floats(
    e1: ArrayLike, pts1: ArrayLike, pts2: ArrayLike
) -> tuple[Floats, Columns, Columns] | None:
    """Well-formed finite input as Python floats, or None for the full checks to explain."""
    try:
        e = np.asarray(e1, dtype=np.float64)
        p = np.asarray(pts1, dtype=np.float64)
        q = np.asarray(pts2, dtype=np.float64)
    except (TypeError, ValueError):
        return None
    if e.shape not in ((2,), (3,)) or p.shape != (5, 2) or q.shape != (5, 2):
        return None
    el, (x1, y1), (x2, y2) = e.tolist(), p.T.tolist(), q.T.tolist()
    if len(el) == 2:
        el.append(1.0)
    # A sum is finite only if every term is (one that overflows merely takes the slow path).
    if not math.isfinite(sum(el) + sum(x1) + sum(y1) + sum(x2) + sum(y2)) or not any(el):
        return None
    return el, [x1, y1], [x2, y2]


def _canonical(x: float, y: float, w: float) -> Array:
    """``projective.canonical`` of three floats (the same numbers, without its array trip)."""
    pivot = w if w != 0 else max((x, y), key=abs)
    scale = math.copysign(1.0 / math.sqrt(x * x + y * y + w * w), pivot)
    return np.array((x * scale, y * scale, w * scale))


def cremona_epipole(
    e1: Floats, p: Columns, q: Columns, *, checked: bool = False
) -> tuple[float, float, float] | None:
    """The paper's closed form in plain floats: e1 (3,), p and q [xs, ys] -> homogeneous e2.

    Returns None when the input may sit on a degeneracy (a landmark on friend 2, repeated
    or collinear landmarks, all landmarks on one line through friend 2) unless ``checked``
    says the full validation has already accepted it, and when every frame is singular.
    """
    brackets = _brackets(e1, p)
    area2 = _twice_areas(q)
    if not checked and _may_be_degenerate(e1, p, q, brackets, area2):
        return None
    pencil = _antisymmetric(brackets)
    # The best-spread triple of photo-2 landmarks makes the best-conditioned frame; the others
    # are only needed when that frame hits a removable singularity.
    best = area2.index(max(area2))
    e2 = _regular_in_frame(pencil, q, best)
    if e2 is not None:
        return e2
    for choice in sorted(range(len(_TRIPLES)), key=lambda c: -area2[c]):
        e2 = _regular_in_frame(pencil, q, choice)
        if e2 is not None:
            return e2
    return None


def _regular_in_frame(pencil: Any, q: Columns, choice: int) -> tuple[float, float, float] | None:
    """e2 in frame ``_TRIPLES[choice]``, or None where that frame is singular."""
    e2, meet, lines, reciprocal = _in_frame(pencil, q, *_TRIPLES[choice])
    if meet > _SINGULAR**2 * lines and reciprocal > _SINGULAR**2 * meet * meet:
        return e2
    return None


def cremona_batch(e1: Array, p: Array, q: Array) -> Array:
    """The closed form for K problems at once: e1 (K, 3), p and q (K, 5, 2) -> e2 (K, 3).

    Used for Monte Carlo and for hypotheses over subsets of landmarks; rows whose best frame
    is singular come back as NaN (callers treat them as no answer).
    """
    areas = np.stack(_twice_areas(q.transpose(2, 1, 0)), axis=1)
    order = np.array([triple + extras for triple, extras in _TRIPLES])[np.argmax(areas, axis=1)]
    rows = np.arange(len(q))[:, None]
    p_cols, q_cols = p[rows, order].transpose(2, 1, 0), q[rows, order].transpose(2, 1, 0)
    pencil = _antisymmetric(_brackets(e1.T, p_cols))
    e2, meet, lines, reciprocal = _in_frame(pencil, q_cols, (0, 1, 2), (3, 4))
    result = np.stack(e2, axis=1)
    singular = (meet <= _SINGULAR**2 * lines) | (reciprocal <= _SINGULAR**2 * meet * meet)
    result[singular] = np.nan
    return result


# The closed form below runs unchanged on Python floats (one problem, fast) and on numpy
# arrays of shape (K,) (K problems): it uses nothing but arithmetic. Landmarks come as
# columns [xs, ys], so that landmark a is at (xs[a], ys[a]).


def _brackets(e1: Any, p: Any) -> list[Any]:
    """|e1 p_a p_b| for the pairs of ``_PAIRS``: the brackets of the epipolar lines through e1.

    Written out pair by pair: with Python floats, indexing costs as much as the arithmetic.
    """
    ex, ey, ew = e1
    (x0, x1, x2, x3, x4), (y0, y1, y2, y3, y4) = p
    return [
        ex * (y0 - y1) + ey * (x1 - x0) + ew * (x0 * y1 - y0 * x1),
        ex * (y0 - y2) + ey * (x2 - x0) + ew * (x0 * y2 - y0 * x2),
        ex * (y0 - y3) + ey * (x3 - x0) + ew * (x0 * y3 - y0 * x3),
        ex * (y0 - y4) + ey * (x4 - x0) + ew * (x0 * y4 - y0 * x4),
        ex * (y1 - y2) + ey * (x2 - x1) + ew * (x1 * y2 - y1 * x2),
        ex * (y1 - y3) + ey * (x3 - x1) + ew * (x1 * y3 - y1 * x3),
        ex * (y1 - y4) + ey * (x4 - x1) + ew * (x1 * y4 - y1 * x4),
        ex * (y2 - y3) + ey * (x3 - x2) + ew * (x2 * y3 - y2 * x3),
        ex * (y2 - y4) + ey * (x4 - x2) + ew * (x2 * y4 - y2 * x4),
        ex * (y3 - y4) + ey * (x4 - x3) + ew * (x3 * y4 - y3 * x4),
    ]


def _antisymmetric(brackets: list[Any]) -> list[list[Any]]:
    """The pencil as a matrix, ``pencil[a][b] = |e1 p_a p_b| = -pencil[b][a]``."""
    b01, b02, b03, b04, b12, b13, b14, b23, b24, b34 = brackets
    return [
        [0.0, b01, b02, b03, b04],
        [-b01, 0.0, b12, b13, b14],
        [-b02, -b12, 0.0, b23, b24],
        [-b03, -b13, -b23, 0.0, b34],
        [-b04, -b14, -b24, -b34, 0.0],
    ]


def _twice_areas(points: Any) -> list[Any]:
    """Twice the area of each triangle of ``_TRIPLES`` (zero: three collinear landmarks).

    Written out triangle by triangle, in the order of ``_TRIPLES``, as ``_brackets``.
    """
    (x0, x1, x2, x3, x4), (y0, y1, y2, y3, y4) = points
    return [
        abs((x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)),
        abs((x1 - x0) * (y3 - y0) - (y1 - y0) * (x3 - x0)),
        abs((x1 - x0) * (y4 - y0) - (y1 - y0) * (x4 - x0)),
        abs((x2 - x0) * (y3 - y0) - (y2 - y0) * (x3 - x0)),
        abs((x2 - x0) * (y4 - y0) - (y2 - y0) * (x4 - x0)),
        abs((x3 - x0) * (y4 - y0) - (y3 - y0) * (x4 - x0)),
        abs((x2 - x1) * (y3 - y1) - (y2 - y1) * (x3 - x1)),
        abs((x2 - x1) * (y4 - y1) - (y2 - y1) * (x4 - x1)),
        abs((x3 - x1) * (y4 - y1) - (y3 - y1) * (x4 - x1)),
        abs((x3 - x2) * (y4 - y2) - (y3 - y2) * (x4 - x2)),
    ]


def _in_frame(pencil: Any, q: Any, basis: tuple[int, int, int], extras: tuple[int, int]) -> Any:
    """e2 with q_i, q_j, q_k as the projective basis, and the frame's conditioning.

    Returns ``((x, y, w), meet, lines, reciprocal)``: the frame is singular when ``meet``
    (squared norm of the meet of the two reciprocal lines) is tiny against ``lines`` (product
    of their squared norms), or ``reciprocal`` against ``meet**2``.
    """
    i, j, k = basis
    xs, ys = q
    ix, iy, jx, jy, kx, ky = xs[i], ys[i], xs[j], ys[j], xs[k], ys[k]
    # Rows of adj([q_i q_j q_k]): coordinates in the frame where q_i, q_j, q_k are the basis.
    r1x, r1y, r1w = jy - ky, kx - jx, jx * ky - jy * kx
    r2x, r2y, r2w = ky - iy, ix - kx, kx * iy - ky * ix
    r3x, r3y, r3w = iy - jy, jx - ix, ix * jy - iy * jx
    # The conic -A c xy + B b xz + (A - B) a yz = 0 through the basis points and q_extra, with
    # A = [ij][k extra], B = [ik][j extra] and A - B = -[i extra][jk] (Pluecker), maps under
    # the reciprocal (x, y, z) -> (yz, zx, xy) to the line (u1, u2, u3) for extra = l and
    # (v1, v2, v3) for extra = m (written out twice: a loop costs more than the arithmetic).
    pi, pj, pk = pencil[i], pencil[j], pencil[k]
    jk, ik, ij = pj[k], pi[k], pi[j]
    l, m = extras  # noqa: E741
    x, y = xs[l], ys[l]
    u1 = -pi[l] * jk * (r1x * x + r1y * y + r1w)
    u2 = ik * pj[l] * (r2x * x + r2y * y + r2w)
    u3 = -ij * pk[l] * (r3x * x + r3y * y + r3w)
    x, y = xs[m], ys[m]
    v1 = -pi[m] * jk * (r1x * x + r1y * y + r1w)
    v2 = ik * pj[m] * (r2x * x + r2y * y + r2w)
    v3 = -ij * pk[m] * (r3x * x + r3y * y + r3w)
    x, y, z = u2 * v3 - u3 * v2, u3 * v1 - u1 * v3, u1 * v2 - u2 * v1
    s, t, w = y * z, z * x, x * y  # the reciprocal again: back to the frame of the conics
    e2 = (s * ix + t * jx + w * kx, s * iy + t * jy + w * ky, s + t + w)
    meet = x * x + y * y + z * z
    norms = (u1 * u1 + u2 * u2 + u3 * u3) * (v1 * v1 + v2 * v2 + v3 * v3)
    return e2, meet, norms, s * s + t * t + w * w


def _may_be_degenerate(e1: Floats, p: Columns, q: Columns, brackets: Floats, area2: Floats) -> bool:
    """Cheap test that fires on all input ``validation.landmark_pairs`` would refuse.

    With ``s`` a photo's spread and ``t = _NEAR_ZERO * s`` its tolerance (as there), twice the
    area of a triangle is at most ``t s`` when two of its corners are repeated (within ``t``),
    and at most ``4 t s`` when all landmarks are collinear (within ``t`` of one line: sides
    across it of at most ``2 t``, along it of at most ``s``). So:

    * photo 2, repeated or collinear landmarks: the smallest of ``area2``;
    * photo 1, collinear landmarks: the triangle p_0 p_1 p_2 (every triangle is small);
    * photo 1, repeated landmarks, one on friend 2 ``e = (x, y) / w``, or all on one line
      through it (also at infinity): some bracket ``|e1 p_a p_b|``, which is
      ``|w| |(p_a - e) x (p_b - e)|``, is at most ``t`` times ``|w| |p_a - e|`` or ``|w| s``
      (``|(x, y)|`` at infinity), all at most ``r_0 + |w| s`` with ``r_0 = |w p_0 - (x, y)|``.

    ``_size`` bounds ``s`` from above, so the test errs towards the full checks.
    """
    ex, ey, ew = e1
    (x1, y1), (x2, y2) = p, q
    size1, size2 = _size(x1, y1), _size(x2, y2)
    if min(area2) <= _COLLINEAR * size2 * size2:
        return True
    p012 = (x1[1] - x1[0]) * (y1[2] - y1[0]) - (y1[1] - y1[0]) * (x1[2] - x1[0])
    if abs(p012) <= _COLLINEAR * size1 * size1:
        return True
    reach = math.hypot(ew * x1[0] - ex, ew * y1[0] - ey) + abs(ew) * size1
    return min(map(abs, brackets)) <= _MARGIN * _NEAR_ZERO * size1 * reach


def _size(xs: Floats, ys: Floats) -> float:
    """Width plus height of the bounding box plus 1 px: at least ``validation.spread``."""
    xs, ys = sorted(xs), sorted(ys)  # one call each instead of min and max
    return xs[-1] - xs[0] + ys[-1] - ys[0] + 1.0
