"""Where a landmark must be in the other photo: its epipolar line, widened by how sure it is.

The line ``l`` of :meth:`.epipolar.Epipolar.line` is uncertain; at a point ``x`` on it, the
line's offset across itself has variance ``x~^T C_l x~`` (``x~ = (x, y, 1)``, ``l`` scaled
to a unit normal), to first order. The band is the centre line with ``z`` of those
standard deviations on each side (``z = 1.96`` at 95 %): narrow near the answer's
landmarks and the other friend, wider far from them. It is a pointwise band: at the true
position of the landmark, the truth is inside it with probability ``level`` (measured in
``docs/suggestions.md``).

A tap in photo B is checked against the same numbers: its distance from the centre line
in standard deviations of the line's offset there and of the tap itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from .. import linalg
from ..drawing.shapes import Point
from ..estimation.uncertainty import chi2_quantile
from ..projective import Array
from ..result import Pixel
from .epipolar import Epipolar

LEVEL = 0.95
# A tap this many standard deviations off the band's centre line does not fit: 1 in 2000
# right taps would be flagged by chance if the band were exact (measured in
# docs/suggestions.md).
FLAG_SIGMAS = 3.5
_OUTLINE_STATIONS = 17  # points along each side of the drawn outline


class BandShape(BaseModel):
    """The band as a phone draws it, in photo B's stored pixels (x right, y down)."""

    model_config = ConfigDict(frozen=True)

    start: Pixel = Field(
        description="One end of the centre line inside the photo (the end "
        "nearer the other friend when the geometry is oriented)."
    )
    end: Pixel = Field(description="The other end of the centre line.")
    half_width: tuple[float, float] = Field(
        description="Half the band's width at `start` and at `end`, px."
    )
    # Drawn, so sent at 0.01 px as the answer's drawing is (shapes.Px): a band's outline
    # was 1.4 kB of each answer event at full precision, one per landmark still to find.
    outline: list[Point] = Field(description="The band's outline, clipped to the photo.")
    level: float = Field(description="Probability that the landmark is inside the band.")


class TapCheck(BaseModel):
    """Whether a tap in photo B fits the band of the landmark it claims to be."""

    model_config = ConfigDict(frozen=True)

    sigmas: float = Field(
        description="Distance from the band's centre line, in standard "
        "deviations of the line there and of the tap."
    )
    fits: bool = Field(
        description=f"False beyond {FLAG_SIGMAS} standard deviations: the tap "
        "does not fit the others."
    )


@dataclass(frozen=True)
class Band:
    """A landmark's epipolar band in photo B.

    Attributes:
        line: (3,) the centre line, ``line[0]^2 + line[1]^2 = 1``.
        covariance: (3, 3) its covariance.
        start, end: (2,) the centre line's part inside photo B (on the half-line where the
            match can be, from the other friend's side, when the geometry is oriented).
        size: photo B's (width, height), px.
        level: the probability the band is drawn at.
    """

    line: Array
    covariance: Array
    start: Array
    end: Array
    size: tuple[int, int]
    level: float = LEVEL

    @property
    def z(self) -> float:
        """Standard deviations on each side at ``level`` (two-sided normal quantile: the
        square root of the chi-square quantile with one degree of freedom)."""
        return math.sqrt(chi2_quantile(self.level, 1))

    @property
    def length(self) -> float:
        return float(np.hypot(*(self.end - self.start)))

    def sd(self, points: Array) -> Array:
        """(N,) standard deviation (px) of the line's offset at the feet of (N, 2) points."""
        feet = points - np.outer(points @ self.line[:2] + self.line[2], self.line[:2])
        lifted = np.column_stack([feet, np.ones(len(feet))])
        return np.sqrt(np.maximum(np.einsum("ni,ij,nj->n", lifted, self.covariance, lifted), 0.0))

    def half_width(self, points: Array) -> Array:
        """(N,) half the band's width (px) at the feet of (N, 2) points."""
        return self.z * self.sd(points)

    def along(self, count: int) -> Array:
        """(count, 2) points evenly spaced on the centre line from start to end."""
        fractions = np.linspace(0.0, 1.0, count)[:, None]
        return self.start + fractions * (self.end - self.start)

    def outline(self) -> Array:
        """(M, 2) the band's outline (both sides, along the line and back), clipped to the
        photo."""
        centre = self.along(_OUTLINE_STATIONS)
        offsets = self.half_width(centre)[:, None] * self.line[None, :2]
        polygon = np.vstack([centre + offsets, (centre - offsets)[::-1]])
        return _clip_to_rectangle(polygon, self.size)

    def shape(self) -> BandShape:
        """What the phone draws."""
        ends = self.half_width(np.array([self.start, self.end]))
        return BandShape(
            start=_pixel(self.start),
            end=_pixel(self.end),
            half_width=(float(ends[0]), float(ends[1])),
            outline=[_pixel(point) for point in self.outline()],
            level=self.level,
        )

    def check(self, tap: Array, tap_covariance: Array, *, limit: float = FLAG_SIGMAS) -> TapCheck:
        """How far a tap (2,) with covariance (2, 2) px^2 is from the centre line."""
        offset = float(self.line[:2] @ tap + self.line[2])
        normal = self.line[:2]
        variance = float(
            self.sd(np.asarray(tap, float)[None])[0] ** 2 + normal @ tap_covariance @ normal
        )
        sigmas = abs(offset) / math.sqrt(variance) if variance > 0 else math.inf
        return TapCheck(sigmas=sigmas, fits=sigmas <= limit)


def epipolar_band(
    epipolar: Epipolar,
    point: Array,
    *,
    image_size: tuple[int, int],
    point_covariance: Array,
    level: float = LEVEL,
) -> Band | None:
    """The band in photo B of a landmark tapped at ``point`` (2,) in photo A.

    Args:
        epipolar: the answer's geometry from A to B (oriented, to keep the half of the line
            the landmark can be on).
        point: where the landmark was tapped in A, px.
        image_size: photo B's (width, height), px.
        point_covariance: (2, 2) the tap's covariance, px^2 (``tap_sigma^2 I``).
        level: the probability the band is drawn at.

    Returns:
        The band, or None when its line does not cross photo B (the landmark cannot be in
        it) or ``point`` has no line: it is the epipole in A exactly (a landmark tapped on
        the other friend's mark). Near it the line's covariance, to first order, widens the
        band to what the taps allow.
    """
    lined = epipolar.line(np.asarray(point, float), point_covariance)
    if lined is None:  # tapped exactly on the other friend: on the line through both phones
        return None
    line, covariance = lined
    segment = _clip_line(line, image_size)
    if segment is None:
        return None
    start, end = segment
    e_b = epipolar.epipole_b
    if epipolar.sign != 0 and abs(e_b[2]) > 1e-12 * linalg.norm(e_b):
        # Keep the half-line from the other friend (e_B) on which the match lies.
        origin = e_b[:2] / e_b[2]
        direction = epipolar.direction(np.asarray(point, float)[None])[0]
        t_start, t_end = (start - origin) @ direction, (end - origin) @ direction
        low, high = max(0.0, min(t_start, t_end)), max(t_start, t_end)
        if high <= low:
            return None
        start, end = origin + low * direction, origin + high * direction
    return Band(line, covariance, start, end, image_size, level)


def _clip_line(line: Array, size: tuple[int, int]) -> tuple[Array, Array] | None:
    """The two ends of the part of ``line`` (unit normal) inside [0, W] x [0, H]."""
    width, height = size
    a, b, c = line
    ends: list[tuple[float, float]] = []
    if abs(b) > 1e-12:
        for x in (0.0, float(width)):
            y = -(a * x + c) / b
            if 0.0 <= y <= height:
                ends.append((x, y))
    if abs(a) > 1e-12:
        for y in (0.0, float(height)):
            x = -(b * y + c) / a
            if 0.0 <= x <= width:
                ends.append((x, y))
    if len(ends) < 2:
        return None
    points = np.array(ends)
    direction = np.array([b, -a])
    order = np.argsort(points @ direction)
    first, last = points[order[0]], points[order[-1]]
    if np.hypot(*(last - first)) < 1.0:
        return None
    return first, last


def _clip_to_rectangle(polygon: Array, size: tuple[int, int]) -> Array:
    """(M, 2) the polygon (N, 2) clipped to [0, W] x [0, H] (Sutherland-Hodgman: the band
    is not convex, the rectangle is)."""
    width, height = size
    edges = ((0, 0.0, 1.0), (0, float(width), -1.0), (1, 0.0, 1.0), (1, float(height), -1.0))
    points = [tuple(p) for p in polygon]
    for axis, bound, side in edges:
        kept: list[tuple[float, ...]] = []
        for index, current in enumerate(points):
            previous = points[index - 1]
            inside_now = side * (current[axis] - bound) >= 0
            inside_before = side * (previous[axis] - bound) >= 0
            if inside_now != inside_before:
                fraction = (bound - previous[axis]) / (current[axis] - previous[axis])
                kept.append(
                    tuple(p + fraction * (c - p) for p, c in zip(previous, current, strict=True))
                )
            if inside_now:
                kept.append(current)
        points = kept
        if not points:
            break
    return np.array(points, dtype=float).reshape(-1, 2)


def _pixel(point: Array) -> Pixel:
    return float(point[0]), float(point[1])
