"""The visible pieces of a conic ``x^T C x = 0`` and of a line, clipped to a photo.

Answers can be anywhere up to infinity and curves any size, so a curve is found where it
crosses the photo's pixel columns and rows rather than along a parametrisation that can run
off to infinity: one routine then handles ellipses, parabolas, both branches of a hyperbola
and line pairs alike, in time proportional to the photo's side. Every stretch of the curve
is within 45 degrees of the rows or of the columns, so one of the two scans samples it at
least once per pixel; each scan keeps the stretches it samples densely.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from ..projective import Array
from .shapes import Polyline

# Points of a scan closer than this across (px, one column apart) belong to one stretch:
# a little over 1 so that the column and row stretches overlap where the curve is at 45 deg.
_DENSE = 1.5
# How far a simplified polyline may stray from the sampled curve, px.
_TOLERANCE = 0.25


def conic_polylines(
    conic: Array, width: int, height: int, origin: Array | None = None
) -> list[Polyline]:
    """The visible pieces of the curve ``x^T C x = 0`` on a ``width`` x ``height`` photo.

    Args:
        conic: (3, 3) symmetric, in px relative to ``origin`` (default (0, 0)): a far-away
            ellipse drawn relative to its centre loses no precision.
        width, height: the photo's size, px; points stay within half a pixel of it.
        origin: (2,) px.

    Returns:
        Polylines in photo px, each sampled at most ~1.4 px apart and then simplified to
        within 0.25 px (Douglas-Peucker, ``cv2.approxPolyDP``).
    """
    ox, oy = (0.0, 0.0) if origin is None else (float(origin[0]), float(origin[1]))
    swap = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    pieces = _stretches(_crossings(conic, width, height, ox, oy))
    rows = _crossings(swap @ conic @ swap, height, width, oy, ox)
    pieces += [piece[:, ::-1] for piece in _stretches(rows)]
    return [simplified(piece) for piece in pieces]


def _crossings(conic: Array, count: int, extent: int, along: float, across: float) -> Array:
    """(count, 2) the conic's two crossings t of each pixel line s = 0 .. count - 1, NaN
    where it has none with -0.5 <= t <= extent - 0.5; relative to the point (along, across).
    Each line's crossings are in ascending order, NaN last."""
    s = np.arange(count, dtype=np.float64)
    x = s - along
    # C(x, y) = a y^2 + b y + c on each line; the stable pair of roots (Numerical Recipes 5.6).
    a = conic[1, 1]
    b = 2.0 * (conic[0, 1] * x + conic[1, 2])
    c = conic[0, 0] * x**2 + 2.0 * conic[0, 2] * x + conic[2, 2]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        q = -0.5 * (b + np.copysign(np.sqrt(b * b - 4.0 * a * c), b))
        t = np.column_stack([q / a, c / q]) + across
    keep = np.isfinite(t) & (t >= -0.5) & (t <= extent - 0.5)
    return np.sort(np.where(keep, t, np.nan), axis=1)


def _stretches(roots: Array) -> list[Array]:
    """(k, 2) runs of crossings (s, t), one line apart and at most ``_DENSE`` px apart
    across: the stretches of the curve this scan samples densely (the other scan samples
    the rest), in the order they end.

    Each crossing on line s + 1, in ascending order, continues the nearest unclaimed one on
    line s within ``_DENSE``. A line has at most two crossings, so this greedy matching is
    a few array operations over all lines at once; the runs are then the chains of links,
    labelled by pointer jumping (log of the photo's side passes).
    """
    crossed = np.flatnonzero(~np.isnan(roots[:, 0]))
    if len(crossed) < 2:
        return []
    offset = crossed[0]  # only the lines the curve crosses, from the first to the last
    roots = roots[offset : crossed[-1] + 1]
    count = len(roots)
    here, there = roots[:-1], roots[1:]  # line s, line s + 1
    gaps = np.abs(there[:, :, None] - here[:, None, :])  # (count - 1, next slot, slot)
    gaps = np.where(np.isnan(gaps), np.inf, gaps)
    rows = np.arange(count - 1)
    first = np.argmin(gaps[:, 0, :], axis=1)  # the first crossing claims its nearest
    first_linked = gaps[rows, 0, first] <= _DENSE
    second_gaps = gaps[:, 1, :].copy()
    second_gaps[rows[first_linked], first[first_linked]] = np.inf  # already claimed
    second = np.argmin(second_gaps, axis=1)
    second_linked = second_gaps[rows, second] <= _DENSE
    # Crossing (s, slot) has node number 2 s + slot; each node's predecessor, or itself.
    nodes = np.arange(2 * count)
    before = nodes.copy()
    before[2 * rows[first_linked] + 2] = 2 * rows[first_linked] + first[first_linked]
    before[2 * rows[second_linked] + 3] = 2 * rows[second_linked] + second[second_linked]
    start = before
    while True:  # pointer jumping: each node's run starts where its chain does
        further = start[start]
        if np.array_equal(further, start):
            break
        start = further
    present = ~np.isnan(roots.reshape(-1))
    nodes, start = nodes[present], start[present]
    order = np.lexsort((nodes, start))  # by run, then along it
    nodes, start = nodes[order], start[order]
    cuts = np.flatnonzero(np.diff(start)) + 1
    points = np.column_stack([(nodes // 2 + offset).astype(np.float64), roots.reshape(-1)[nodes]])
    bounds = np.r_[0, cuts, len(nodes)]
    last = nodes[bounds[1:] - 1]  # each run's last node: where it ends
    long = np.flatnonzero(np.diff(bounds) > 1)  # a lone crossing is sampled by the other scan
    return [points[bounds[i] : bounds[i + 1]] for i in long[np.argsort(last[long], kind="stable")]]


def simplified(points: Array) -> Polyline:
    """The polyline within 0.25 px of the (N, 2) ``points`` (Douglas-Peucker): the answer's
    curves are sampled finely, then thinned to what a drawing needs."""
    line = points.reshape(-1, 1, 2).astype(np.float32)
    kept = cv2.approxPolyDP(line, _TOLERANCE, False).reshape(-1, 2)
    return [(float(x), float(y)) for x, y in kept]


def clip_line(line: Array, width: int, height: int) -> tuple[Array, Array] | None:
    """The two ends of line ``a x + b y + c = 0`` on the photo's border, or None if it misses."""
    a, b, c = line / max(np.abs(line[:2]).max(), 1e-300)
    if not (math.isfinite(a) and math.isfinite(b) and math.isfinite(c)) or a == b == 0:
        return None
    ends = [np.array([x, -(a * x + c) / b]) for x in (0.0, width) if b != 0]
    ends += [np.array([-(b * y + c) / a, y]) for y in (0.0, height) if a != 0]
    pad = 1e-6
    inside = [e for e in ends if -pad <= e[0] <= width + pad and -pad <= e[1] <= height + pad]
    if len(inside) < 2:
        return None
    pairs = [(p, q) for i, p in enumerate(inside) for q in inside[i + 1 :]]
    start, end = max(pairs, key=lambda pq: float(np.hypot(*(pq[0] - pq[1]))))
    return start, end
