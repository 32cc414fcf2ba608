"""The friend's marker: the open frame on photo 2 (and on a phone's photo where the friend
was found), the sight on photo 1's tapped friend. Both are open in the middle, so the
friend shows through."""

from __future__ import annotations

import math

import numpy as np

from .. import words
from ..projective import Array
from ..result import Ellipse
from .curves import conic_polylines
from .shapes import FrameShape, Point, Polyline, SightShape
from .sizes import BRACKET_ARM, LONG_REGION, OUTLINED_REGION, Sizes

# A zero axis would make the ellipse's matrix infinite; thinner than this is a line anyway.
_THINNEST_AXIS_PX = 1e-3


def frame(at: Array, ellipse: Ellipse | None, sizes: Sizes) -> FrameShape:
    """Corner brackets around the friend at ``at`` (2,) px and their 95 % region
    ``ellipse`` (or, without one, a region as large as a person), the region's outline inside
    when it is larger than a person, and "friend" ("friend?" without a region) on a leader."""
    visible, outlined = frame_box(ellipse, sizes)
    outline = ellipse_polylines(ellipse, sizes) if ellipse is not None and outlined else []
    arm = BRACKET_ARM * float(visible.min())
    brackets: list[Polyline] = []
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            corner = at + visible * np.array([sx, sy])
            brackets.append(
                [_point(corner - [0.0, sy * arm]), _point(corner), _point(corner - [sx * arm, 0.0])]
            )
    # Above the frame, else below it when there is no room above.
    gap = 0.6 * sizes.frame_half
    above = bool(at[1] - visible[1] - gap - sizes.label_height >= 0)
    edge = at[1] - visible[1] if above else at[1] + visible[1]
    level = edge - gap if above else edge + gap
    return FrameShape(
        centre=_point(at),
        half=_point(visible),
        brackets=brackets,
        outline=outline,
        sure=ellipse is not None,
        label=words.DRAWN_FRIEND if ellipse is not None else words.DRAWN_FRIEND_LIKELY,
        label_above=above,
        leader=((float(at[0]), float(edge)), (float(at[0]), float(level))),
    )


def frame_box(ellipse: Ellipse | None, sizes: Sizes) -> tuple[Array, bool]:
    """(2,) the frame's half-sizes around ``ellipse`` (at least a person's each way, at most
    the photo's width + height: a huge region's corners), and whether the region is large
    enough for its outline to be drawn."""
    half = np.array([sizes.frame_half, sizes.frame_half])
    outlined = False
    if ellipse is not None and all(map(math.isfinite, (*ellipse.center, *ellipse.axes))):
        a, b = ellipse.axes
        theta = math.radians(ellipse.angle_deg)
        cos, sin = abs(math.cos(theta)), abs(math.sin(theta))
        # The axis-aligned half-sizes of the ellipse, a little room added.
        reach = np.array([math.hypot(a * cos, b * sin), math.hypot(a * sin, b * cos)])
        half = np.maximum(half, 1.1 * reach + sizes.room)
        # Not across the person the brackets frame, unless the region is long enough for its
        # outline to be the answer (a line to look along).
        wide = min(a, b) >= OUTLINED_REGION * sizes.frame_half
        outlined = wide or max(a, b) >= LONG_REGION * sizes.frame_half
    return np.minimum(half, [sizes.width + sizes.height] * 2), outlined


def ellipse_polylines(ellipse: Ellipse, sizes: Sizes) -> list[Polyline]:
    """The visible part of ``ellipse``, whatever its size and position."""
    values = (*ellipse.center, *ellipse.axes, ellipse.angle_deg)
    if not all(map(math.isfinite, values)):
        return []
    a, b = (max(float(axis), _THINNEST_AXIS_PX) for axis in ellipse.axes)
    theta = math.radians(ellipse.angle_deg)
    first = np.array([math.cos(theta), math.sin(theta)])
    second = np.array([-first[1], first[0]])
    shape = np.outer(first, first) / a**2 + np.outer(second, second) / b**2
    # Relative to its centre, so a far-away ellipse loses no precision: d^T Q d = 1.
    conic = np.zeros((3, 3))
    conic[:2, :2] = shape
    conic[2, 2] = -1.0
    return conic_polylines(conic, sizes.width, sizes.height, origin=np.array(ellipse.center))


def sight(at: Array, sizes: Sizes) -> SightShape:
    """A ring with four ticks (a gun sight) on ``at`` (2,) px, open in the middle."""
    directions = np.array([(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)])
    ticks = [
        (_point(at + 0.3 * sizes.marker_radius * d), _point(at + sizes.marker_radius * d))
        for d in directions
    ]
    return SightShape(centre=_point(at), radius=0.6 * sizes.marker_radius, ticks=ticks)


def _point(point: Array) -> Point:
    return float(point[0]), float(point[1])
