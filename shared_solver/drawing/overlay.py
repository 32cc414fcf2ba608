"""Drawing the answer on a photo, for the phone that took it.

The friend must stay visible: nothing is drawn on the spot where they are. Photo 2 (the
photo the friend was found in) gets an open frame: corner brackets around the 95 % region
(never smaller than a person far across a hall), the region's outline thin inside them, and
"friend" on a short leader beside; an arrow at the border when the friend is outside the
photo or at infinity; the curve the friend is on, labelled, when only 4 landmarks were
marked and the cameras are unknown. Photo 1 (the photo the friend was tapped in) gets the
tapped friend as a sight open in the middle. Both get the landmarks as thin rings with a
centre dot, coloured by number (:mod:`.palette`, the same colours on both phones), their
numbers beside them, and mis-tap suspects ringed in red. The friend's frame is drawn last,
on top of everything. The phone app draws the same design (docs/app.md).

Answers can be anywhere up to infinity and ellipses any size, so every position stays a float
until it has been clipped to the photo: OpenCV takes int coordinates and would overflow.
Curves are found where they cross the photo's pixel rows and columns rather than along a
parametrisation that can run off to infinity: one routine then draws ellipses, parabolas,
both branches of a hyperbola and line pairs alike, in time proportional to the photo's side.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import validation, words
from ..errors import ErrorCode, SolverError
from ..projective import Array, to_pixel
from ..result import Ellipse, Homogeneous, Pixel, SolveResult
from .palette import (
    FRIEND_COLOUR_BGR,
    OUTLINE_COLOUR_BGR,
    SUSPECT_COLOUR_BGR,
    Bgr,
    landmark_colour,
)

Image = NDArray[np.uint8]
# Which photo of the answer this is: 1, the friend was tapped in it (epipole1); 2, the
# friend was found in it (epipole2).
Photo = Literal[1, 2]

# OpenCV's fixed point: coordinates in 1/16 px place markers with sub-pixel accuracy.
_SHIFT = 4
_ONE = 1 << _SHIFT
_FONT = cv2.FONT_HERSHEY_SIMPLEX
_AA = cv2.LINE_AA
# A zero axis would make the ellipse's matrix infinite; thinner than this is a line anyway.
_THINNEST_AXIS_PX = 1e-3
# An arrow's head: its length as a fraction of the arrow's, and as wide as it is long.
_ARROW_HEAD = 0.3
# Beyond this many photo diagonals a distance in px means nothing to a person: "far off".
_FAR_OFF_DIAGONALS = 100
# A suspect's red ring: its radius in landmark rings.
_SUSPECT_RING = 1.8
# A bracket's arm, as a fraction of the frame's shorter half-side.
_BRACKET_ARM = 0.4
# The region's outline is drawn when its long semi-axis is at least this many frame
# half-sizes: smaller, it would run over the friend, whom the brackets frame anyway.
_OUTLINED_REGION = 0.6

# Draws a shape in a colour, its strokes widened by the given px (0 = as designed).
_Shape = Callable[[Bgr, int], None]


@dataclass(frozen=True)
class _Style:
    """Sizes in px for one photo; all grow with its diagonal, so they read on a phone."""

    width: int
    height: int
    line: int
    outline: int
    font_scale: float
    text_thickness: int
    marker_radius: float
    landmark_radius: float
    frame_half: float
    margin: float
    arrow_length: float

    @classmethod
    def of(cls, width: int, height: int) -> _Style:
        diagonal = math.hypot(width, height)
        # Thin: a stroke hides what is under it. A phone shows the whole photo across its
        # screen (one screen px is about diagonal / 700 photo px): 1-2 screen px.
        line = max(2, round(diagonal / 900))
        # That keeps numbers ~10 pt high on the phone.
        font_scale = diagonal / 1100
        return cls(
            width=width,
            height=height,
            line=line,
            outline=max(2, round(0.6 * line)),
            font_scale=font_scale,
            text_thickness=max(1, round(font_scale * 2)),
            marker_radius=diagonal / 45,
            landmark_radius=max(5.0, diagonal / 160),
            # The frame around the friend is never smaller than a person 80 m away on a
            # phone's main camera (about 1.5 % of the diagonal), with room around them.
            frame_half=diagonal / 55,
            margin=diagonal / 30,
            arrow_length=diagonal / 7,
        )

    @property
    def centre(self) -> Array:
        return np.array([self.width / 2, self.height / 2])

    def contains(self, point: Array, pad: float = 0.0) -> bool:
        """Whether ``point`` is on the photo (edges at 0 and width/height), or within ``pad``."""
        x, y = point
        return bool(-pad <= x <= self.width + pad and -pad <= y <= self.height + pad)


def draw_overlay(
    image: NDArray[Any],
    result: SolveResult,
    *,
    photo: Photo = 2,
    points: ArrayLike | None = None,
    labels: Sequence[int] | None = None,
    epipolar_lines: bool = False,
) -> Image:
    """The photo with the answer drawn on it, for the phone that took it.

    ``photo=2`` (the friend found, ``result.epipole2``): an open yellow frame, corner
    brackets around the 95 % ellipse of ``result.uncertainty`` (at least ``frame_half`` each
    way, so a small region still frames a person) with the ellipse's outline inside and
    "friend" on a leader beside it ("friend?" without a region); nothing inside the frame
    but that outline, so the friend shows through. When the friend is outside the photo, an
    arrow at the border pointing from the photo's centre towards them with "friend N px off"
    (N as in ``solve``'s warning: px beyond the nearest edge), or "friend far off this way"
    when ``epipole2`` is at infinity (``epipole2_h`` has ``w == 0``; the arrow follows its
    oriented ``(x, y)``). When the friend is behind this camera (``epipole2_h`` oriented with
    ``w < 0``) no point of the photo is right: a banner says "friend is behind you" (or
    "position unclear" for a 'poor' answer). With 4 landmarks (``method="conic"``) the
    curve ``x^T conic2 x = 0`` the friend is on, labelled, and no point. Other exact
    candidates (``result.candidates``: 6 landmarks on a line, or 7) as thin "?" circles.

    ``photo=1`` (the friend tapped, ``result.epipole1``, refined): a sight, open in the
    middle so the tapped person stays visible; the same border arrow when it is outside.

    Both: each landmark a thin ring in its number's colour with a dot at its centre
    (:func:`.palette.landmark_colour`, identical on both phones) and its number beside it;
    suspects (``result.suspect_landmarks``) ringed in red, their number followed by "?". The
    friend's frame or sight is drawn last, over the rest. Sizes, strokes and text scale with
    the photo's diagonal.

    Args:
        image: (H, W, 3) uint8 BGR photo (OpenCV's layout), or (H, W) uint8 grey; never
            modified.
        result: what :func:`.solve` returned for these photos.
        photo: which photo of the answer this is: 2 (where the friend was found) or 1 (where
            the friend was tapped).
        points: (N, 2) landmarks of this photo, pixels (x right, y down), in the order given
            to ``solve`` (the indices of ``suspect_landmarks`` refer to it).
        labels: the numbers people see on the landmarks, one per point (default 1..N).
        epipolar_lines: also draw each landmark's epipolar line in this photo, the line
            through the landmark and the friend's position (``epipole2_h`` on photo 2,
            ``epipole1_h`` on photo 1, so also when that is at infinity), in the
            landmark's colour. Nothing when the position is unknown (``method="conic"``).

    Returns:
        A new (H, W, 3) uint8 BGR image, the same size as ``image``.

    Raises:
        SolverError: ``INVALID_SHAPE`` for an image that is not (H, W, 3) or (H, W) uint8,
            or points that are not (N, 2) numbers; ``NOT_FINITE`` for NaN or infinite
            points; ``MISMATCHED_LENGTHS`` when ``labels`` and ``points`` differ in length;
            ``INVALID_PARAMETER`` for a ``photo`` other than 1 or 2.
    """
    canvas = _bgr_copy(image)
    landmarks, names = _landmarks(points, labels)
    if photo not in (1, 2):
        raise SolverError(ErrorCode.INVALID_PARAMETER, words.bad_photo(photo))
    style = _Style.of(canvas.shape[1], canvas.shape[0])
    ellipse = result.uncertainty.ellipse if result.uncertainty is not None else None
    marker: Callable[[Image, Array, _Style], None]
    if photo == 2:
        friend, friend_h = result.epipole2, result.epipole2_h
        others = [c.epipole2 for c in result.candidates]
        sure = ellipse is not None

        def marker(canvas: Image, at: Array, style: _Style) -> None:
            _draw_frame(canvas, at, ellipse if sure else None, style)

    else:
        friend, friend_h = result.epipole1, result.epipole1_h
        others = [c.epipole1 for c in result.candidates]
        marker = _draw_sight
    if epipolar_lines and friend_h is not None:
        _draw_epipolar_lines(canvas, np.array(friend_h), landmarks, names, style)
    _draw_landmarks(canvas, landmarks, names, set(result.suspect_landmarks), style)
    _draw_other_candidates(canvas, others, friend, style)
    if photo == 2 and result.conic2 is not None:
        samples = _conic_samples(np.array(result.conic2), style)
        _draw_curve(canvas, samples, style.line, style)
        _label_curve(canvas, samples, style)
    if friend is None and friend_h is not None and _behind(friend_h):
        # Behind the camera: no point of this photo is right. Say so, as solve's warning does.
        pinned = result.quality != "poor"
        text = words.DRAWN_BEHIND if pinned else words.DRAWN_UNCLEAR
        _centred_text(
            canvas, text, np.array([style.width / 2, style.margin]), FRIEND_COLOUR_BGR, style
        )
    else:
        _draw_friend(canvas, friend, friend_h, marker, style)
    return canvas


def _behind(homogeneous: Homogeneous) -> bool:
    """An oriented position with ``w < 0`` that is not at infinity: behind the camera."""
    return homogeneous[2] < 0 and to_pixel(np.array(homogeneous)) is not None


# --- input ------------------------------------------------------------------------------


def _bgr_copy(image: Any) -> Image:
    """A contiguous (H, W, 3) uint8 copy of the photo to draw on."""
    if not isinstance(image, np.ndarray) or image.dtype != np.uint8:
        raise SolverError(ErrorCode.INVALID_SHAPE, words.NOT_8_BIT)
    photo: Image = image
    if photo.ndim == 3 and photo.shape[2] == 1:
        photo = photo[:, :, 0]
    if photo.size > 0 and photo.ndim == 2:
        return np.asarray(cv2.cvtColor(np.ascontiguousarray(photo), cv2.COLOR_GRAY2BGR), np.uint8)
    if photo.size > 0 and photo.ndim == 3 and photo.shape[2] == 3:
        return photo.copy(order="C")
    raise SolverError(
        ErrorCode.INVALID_SHAPE,
        words.not_a_photo(image.shape),
    )


def _landmarks(points: ArrayLike | None, labels: Sequence[int] | None) -> tuple[Array, list[int]]:
    if points is None:
        if labels is not None and len(labels) > 0:
            raise SolverError(ErrorCode.MISMATCHED_LENGTHS, words.LABELS_WITHOUT_POINTS)
        return np.zeros((0, 2)), []
    landmarks = validation.points(points, "points")
    if labels is None:
        return landmarks, list(range(1, len(landmarks) + 1))
    try:
        names = [int(label) for label in labels]
    except (TypeError, ValueError) as error:
        raise SolverError(ErrorCode.INVALID_SHAPE, words.LABELS_NOT_WHOLE) from error
    if len(names) != len(landmarks):
        raise SolverError(
            ErrorCode.MISMATCHED_LENGTHS,
            words.labels_mismatch(len(names), len(landmarks)),
        )
    return landmarks, names


# --- what is drawn ----------------------------------------------------------------------


def _draw_friend(
    canvas: Image,
    pixel: Pixel | None,
    homogeneous: Homogeneous | None,
    marker: Callable[[Image, Array, _Style], None],
    style: _Style,
) -> None:
    """The friend's marker, or an arrow at the border when they are off the photo."""
    if pixel is not None and all(map(math.isfinite, pixel)):
        at = np.array(pixel)
        if style.contains(at):
            marker(canvas, at, style)
            return
        x, y = pixel
        # The same "beyond the edge" distance as solve's warning, so the two numbers agree.
        beyond = max(-x, x - style.width, -y, y - style.height)
        far = beyond > _FAR_OFF_DIAGONALS * math.hypot(style.width, style.height)
        text = words.DRAWN_FAR_OFF if far else words.drawn_off_photo(beyond)
        _draw_border_arrow(canvas, at - style.centre, text, style)
    elif homogeneous is not None and all(map(math.isfinite, homogeneous)):
        # At infinity: solve orients epipoles, so (x, y) points to the friend's side.
        x, y, _ = homogeneous
        direction = np.array([x, y])
        if np.any(direction != 0):
            _draw_border_arrow(canvas, direction, "friend far off this way", style)


def _draw_frame(canvas: Image, at: Array, ellipse: Ellipse | None, style: _Style) -> None:
    """Corner brackets around the friend's region (or, without one, a region as large as a
    person), the region's outline inside, and "friend" on a leader beside: open, so the
    friend shows through."""
    half = np.array([style.frame_half, style.frame_half])
    if ellipse is not None and all(map(math.isfinite, (*ellipse.center, *ellipse.axes))):
        a, b = ellipse.axes
        theta = math.radians(ellipse.angle_deg)
        cos, sin = abs(math.cos(theta)), abs(math.sin(theta))
        # The axis-aligned half-sizes of the ellipse, a little room added.
        reach = np.array([math.hypot(a * cos, b * sin), math.hypot(a * sin, b * cos)])
        half = np.maximum(half, 1.1 * reach + style.line)
        # A region smaller than a person is inside the brackets: its outline would cover them.
        if max(a, b) >= _OUTLINED_REGION * style.frame_half:
            _draw_ellipse(canvas, ellipse, style)
    visible = np.minimum(half, [style.width + style.height] * 2)  # a huge region: its corners
    arm = _BRACKET_ARM * float(visible.min())
    corners = [at + visible * np.array([sx, sy]) for sx in (-1.0, 1.0) for sy in (-1.0, 1.0)]

    def brackets(colour: Bgr, grow: int) -> None:
        for corner in corners:
            inward = np.sign(at - corner)
            for leg in (np.array([inward[0], 0.0]), np.array([0.0, inward[1]])):
                end = corner + arm * leg
                cv2.line(
                    canvas, _fixed(corner), _fixed(end), colour, style.line + grow, _AA, _SHIFT
                )

    _outlined(brackets, FRIEND_COLOUR_BGR, style)
    text = words.DRAWN_FRIEND if ellipse is not None else words.DRAWN_FRIEND_LIKELY
    _leader_label(canvas, text, at, visible, style)


def _leader_label(canvas: Image, text: str, at: Array, half: Array, style: _Style) -> None:
    """``text`` beside the frame (above it, else below), joined to it by a short leader."""
    (_, height), baseline = _text_size(text, style)
    gap = 0.6 * style.frame_half
    above = at[1] - half[1] - gap - height >= 0
    edge = at[1] - half[1] if above else at[1] + half[1]
    level = edge - gap if above else edge + gap
    start = np.array([at[0], edge])
    end = np.array([at[0], level])

    def leader(colour: Bgr, grow: int) -> None:
        cv2.line(canvas, _fixed(start), _fixed(end), colour, style.line + grow, _AA, _SHIFT)

    if style.contains(start) and style.contains(end):
        _outlined(leader, FRIEND_COLOUR_BGR, style)
    centre = end + np.array([0.0, -(height + baseline) / 2 if above else (height + baseline) / 2])
    _centred_text(canvas, text, centre, FRIEND_COLOUR_BGR, style)


def _draw_sight(canvas: Image, at: Array, style: _Style) -> None:
    """A thin ring with four ticks (a gun sight) on ``at``, open in the middle."""
    radius = 0.6 * style.marker_radius
    directions = np.array([(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)])
    ticks = [(at + 0.3 * style.marker_radius * d, at + style.marker_radius * d) for d in directions]

    def ring(colour: Bgr, grow: int) -> None:
        thickness = style.line + grow
        cv2.circle(canvas, _fixed(at), round(radius * _ONE), colour, thickness, _AA, _SHIFT)
        for start, end in ticks:
            cv2.line(canvas, _fixed(start), _fixed(end), colour, thickness, _AA, _SHIFT)

    _outlined(ring, FRIEND_COLOUR_BGR, style)


def _draw_ellipse(canvas: Image, ellipse: Ellipse, style: _Style) -> None:
    """The visible part of the uncertainty ellipse, whatever its size and position."""
    values = (*ellipse.center, *ellipse.axes, ellipse.angle_deg)
    if not all(map(math.isfinite, values)):
        return
    a, b = (max(float(axis), _THINNEST_AXIS_PX) for axis in ellipse.axes)
    theta = math.radians(ellipse.angle_deg)
    first = np.array([math.cos(theta), math.sin(theta)])
    second = np.array([-first[1], first[0]])
    shape = np.outer(first, first) / a**2 + np.outer(second, second) / b**2
    # Relative to its centre, so a far-away ellipse loses no precision: d^T Q d = 1.
    conic = np.zeros((3, 3))
    conic[:2, :2] = shape
    conic[2, 2] = -1.0
    samples = _conic_samples(conic, style, origin=np.array(ellipse.center))
    _draw_curve(canvas, samples, max(1, round(0.75 * style.line)), style)


def _label_curve(canvas: Image, samples: Array, style: _Style) -> None:
    """ "friend on this curve" beside the curve's point nearest the photo's centre."""
    if len(samples) == 0:
        return
    nearest = samples[np.argmin(np.hypot(*(samples - style.centre).T))]
    (_, height), _ = _text_size(words.DRAWN_ON_CURVE, style)
    offset = np.array([0.0, -(style.margin + height)])
    _centred_text(canvas, words.DRAWN_ON_CURVE, nearest + offset, FRIEND_COLOUR_BGR, style)


def _draw_epipolar_lines(
    canvas: Image, epipole: Array, landmarks: Array, labels: list[int], style: _Style
) -> None:
    """Each landmark's epipolar line: the line through it and the epipole (maybe at infinity)."""
    thickness = max(2, style.line // 2)
    for point, label in zip(landmarks, labels, strict=True):
        segment = _clip_line(np.cross(np.append(point, 1.0), epipole), style)
        if segment is None:
            continue
        start, end = segment

        def line(colour: Bgr, grow: int, start: Array = start, end: Array = end) -> None:
            cv2.line(canvas, _fixed(start), _fixed(end), colour, thickness + grow, _AA, _SHIFT)

        _outlined(line, landmark_colour(label), style)


def _draw_other_candidates(
    canvas: Image, others: list[Pixel | None], friend: Pixel | None, style: _Style
) -> None:
    """Other positions that fit the landmarks exactly, as thin "?" circles."""
    radius = 0.7 * style.marker_radius
    for other in others:
        if other is None or not all(map(math.isfinite, other)):
            continue
        at = np.array(other)
        # The answer is refined from one of them: that one is in the frame already.
        if friend is not None and np.hypot(*(at - np.array(friend))) < style.frame_half:
            continue
        if not style.contains(at):
            continue

        def circle(colour: Bgr, grow: int, at: Array = at) -> None:
            thickness = style.line + grow
            cv2.circle(canvas, _fixed(at), round(radius * _ONE), colour, thickness, _AA, _SHIFT)

        _outlined(circle, FRIEND_COLOUR_BGR, style)
        _centred_text(canvas, "?", at, FRIEND_COLOUR_BGR, style)


def _draw_landmarks(
    canvas: Image, landmarks: Array, labels: list[int], suspects: set[int], style: _Style
) -> None:
    """Thin rings with a centre dot in their number's colour, the number beside; suspects
    inside a red ring, number + "?". The spot itself stays visible inside the ring."""
    radius = style.landmark_radius
    dot = max(1.5, 0.6 * style.line)
    for index, (point, label) in enumerate(zip(landmarks, labels, strict=True)):
        if not style.contains(point, pad=style.margin):
            continue
        colour = landmark_colour(label)
        text = str(label)
        if index in suspects:
            text += "?"

            def ring(colour: Bgr, grow: int, centre: tuple[int, int] = _fixed(point)) -> None:
                size = round(_SUSPECT_RING * radius * _ONE)
                cv2.circle(canvas, centre, size, colour, style.line + grow, _AA, _SHIFT)

            _outlined(ring, SUSPECT_COLOUR_BGR, style)
        centre = _fixed(point)

        def ring(colour: Bgr, grow: int, centre: tuple[int, int] = centre) -> None:
            size = round(radius * _ONE)
            cv2.circle(canvas, centre, size, colour, style.line + grow, _AA, _SHIFT)
            cv2.circle(canvas, centre, round((dot + grow / 2) * _ONE), colour, -1, _AA, _SHIFT)

        _outlined(ring, colour, style)
        gap = (_SUSPECT_RING if index in suspects else 1.0) * radius + style.line
        _label_beside(canvas, text, point, gap=gap, colour=colour, style=style)


def _draw_border_arrow(canvas: Image, direction: Array, text: str, style: _Style) -> None:
    """An arrow ending at the border (inset by the margin), on the ray from the photo's
    centre along ``direction``, with ``text`` beside it on the side with more room."""
    unit = direction / np.hypot(*direction)
    half = np.maximum([style.width / 2 - style.margin, style.height / 2 - style.margin], 1.0)
    with np.errstate(divide="ignore"):
        reach = float(np.min(half / np.abs(unit)))
    tip = style.centre + reach * unit
    tail = tip - min(style.arrow_length, 0.8 * reach) * unit
    _draw_arrow(canvas, tail, tip, style)
    (width, height), baseline = _text_size(text, style)
    # Beside the arrow rather than behind it, so a long text still stays near the border; on
    # the side facing the middle of the photo across the arrow, where there is more room.
    across = np.array([-unit[1], unit[0]])
    level = abs(unit[0]) >= abs(unit[1])
    roomier = (
        (0.0, 1.0 if tip[1] <= style.centre[1] else -1.0)
        if level
        else (1.0 if tip[0] <= style.centre[0] else -1.0, 0.0)
    )
    across = across if across @ roomier >= 0 else -across
    head_half_width = _ARROW_HEAD * style.arrow_length / 2
    support = abs(across[0]) * width + abs(across[1]) * (height + baseline)
    clearance = support / 2 + head_half_width + style.line
    centre = (tip + tail) / 2 + clearance * across
    _centred_text(canvas, text, centre, FRIEND_COLOUR_BGR, style)


def _draw_arrow(canvas: Image, tail: Array, tip: Array, style: _Style) -> None:
    """A thick arrow from ``tail`` to ``tip`` with a filled triangular head."""
    length = float(np.hypot(*(tip - tail)))
    unit = (tip - tail) / length
    across = np.array([-unit[1], unit[0]])
    head = min(length, _ARROW_HEAD * style.arrow_length)
    base = tip - head * unit
    triangle = _fixed_points(
        np.array([tip, base + 0.5 * head * across, base - 0.5 * head * across])
    )
    shaft_end = base + 0.2 * head * unit  # into the head, so no seam shows between them
    shaft = 2 * style.line

    def arrow(colour: Bgr, grow: int) -> None:
        cv2.line(canvas, _fixed(tail), _fixed(shaft_end), colour, shaft + grow, _AA, _SHIFT)
        if grow:
            cv2.polylines(canvas, [triangle], True, colour, grow, _AA, _SHIFT)
        cv2.fillPoly(canvas, [triangle], colour, _AA, _SHIFT)

    _outlined(arrow, FRIEND_COLOUR_BGR, style)


def _draw_curve(canvas: Image, samples: Array, thickness: int, style: _Style) -> None:
    """A friend-coloured stroke through ``samples`` (at most ~1.4 px apart along the curve)."""

    centres = [(int(x), int(y)) for x, y in _fixed_points(samples)]  # once for both passes

    def dots(colour: Bgr, grow: int) -> None:
        radius = round((thickness + grow) / 2 * _ONE)
        for centre in centres:
            cv2.circle(canvas, centre, radius, colour, -1, _AA, _SHIFT)

    _outlined(dots, FRIEND_COLOUR_BGR, style)


# --- geometry of what is visible --------------------------------------------------------


def _conic_samples(conic: Array, style: _Style, origin: Array | None = None) -> Array:
    """(M, 2) pixels of the curve ``x^T C x = 0`` on the photo, at most ~1.4 px apart along it.

    One point where the curve crosses each pixel column, one where it crosses each row:
    every stretch of the curve is within 45 degrees of one of the two, so one of the scans
    samples it at least once per pixel. ``conic`` is in pixels relative to ``origin``.
    """
    ox, oy = (0.0, 0.0) if origin is None else (float(origin[0]), float(origin[1]))
    swap = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    columns = _crossings(conic, style.width, style.height, ox, oy)
    rows = _crossings(swap @ conic @ swap, style.height, style.width, oy, ox)
    return np.vstack([columns, rows[:, ::-1]])


def _crossings(conic: Array, count: int, extent: int, along: float, across: float) -> Array:
    """(M, 2) points (s, t) of the conic on the pixel lines s = 0 .. count - 1 where
    -0.5 <= t <= extent - 0.5, in pixels; the conic is relative to the point (along, across)."""
    s = np.arange(count, dtype=np.float64)
    x = s - along
    # C(x, y) = a y^2 + b y + c on each line; the stable pair of roots (Numerical Recipes 5.6).
    a = conic[1, 1]
    b = 2.0 * (conic[0, 1] * x + conic[1, 2])
    c = conic[0, 0] * x**2 + 2.0 * conic[0, 2] * x + conic[2, 2]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        q = -0.5 * (b + np.copysign(np.sqrt(b * b - 4.0 * a * c), b))
        t = np.concatenate([q / a, c / q]) + across
    both = np.concatenate([s, s])
    keep = np.isfinite(t) & (t >= -0.5) & (t <= extent - 0.5)
    return np.column_stack([both[keep], t[keep]])


def _clip_line(line: Array, style: _Style) -> tuple[Array, Array] | None:
    """The two ends of line ``a x + b y + c = 0`` on the photo's border, or None if it misses."""
    a, b, c = line / max(np.abs(line[:2]).max(), 1e-300)
    if not (math.isfinite(a) and math.isfinite(b) and math.isfinite(c)) or a == b == 0:
        return None
    width, height = style.width, style.height
    ends = [np.array([x, -(a * x + c) / b]) for x in (0.0, width) if b != 0]
    ends += [np.array([-(b * y + c) / a, y]) for y in (0.0, height) if a != 0]
    inside = [end for end in ends if style.contains(end, pad=1e-6)]
    if len(inside) < 2:
        return None
    pairs = [(p, q) for i, p in enumerate(inside) for q in inside[i + 1 :]]
    start, end = max(pairs, key=lambda pq: float(np.hypot(*(pq[0] - pq[1]))))
    return start, end


# --- OpenCV primitives ------------------------------------------------------------------


def _outlined(shape: _Shape, colour: Bgr, style: _Style) -> None:
    """A dark version one outline wider all round, then the shape: it reads on any photo."""
    shape(OUTLINE_COLOUR_BGR, 2 * style.outline)
    shape(colour, 0)


def _text_size(text: str, style: _Style) -> tuple[tuple[int, int], int]:
    size, baseline = cv2.getTextSize(
        text, _FONT, style.font_scale, style.text_thickness + 2 * style.outline
    )
    return (int(size[0]), int(size[1])), int(baseline)


def _put_text(
    canvas: Image, text: str, origin: tuple[int, int], colour: Bgr, style: _Style
) -> None:
    """``text`` with its baseline starting at ``origin``, coloured over a dark outline."""
    outline = style.text_thickness + 2 * style.outline
    cv2.putText(canvas, text, origin, _FONT, style.font_scale, OUTLINE_COLOUR_BGR, outline, _AA)
    cv2.putText(canvas, text, origin, _FONT, style.font_scale, colour, style.text_thickness, _AA)


def _centred_text(canvas: Image, text: str, centre: Array, colour: Bgr, style: _Style) -> None:
    """``text`` centred on ``centre``, moved just enough to stay whole on the photo."""
    box = _text_size(text, style)
    (width, height), baseline = box
    corner = (centre[0] - width / 2, centre[1] + (height - baseline) / 2)
    _put_text(canvas, text, _text_origin(corner, box, style), colour, style)


def _label_beside(
    canvas: Image, text: str, point: Array, *, gap: float, colour: Bgr, style: _Style
) -> None:
    """``text`` up and to the right of ``point``, flipped left or down near the edges."""
    box = _text_size(text, style)
    (width, height), _ = box
    x, y = point
    left = x + gap if x + gap + width <= style.width else x - gap - width
    bottom = y - gap if y - gap - height >= 0 else y + gap + height
    _put_text(canvas, text, _text_origin((left, bottom), box, style), colour, style)


def _text_origin(
    corner: tuple[float, float], box: tuple[tuple[int, int], int], style: _Style
) -> tuple[int, int]:
    """Integer baseline origin (bottom left) of a text box, clamped onto the photo."""
    (width, height), baseline = box
    left = min(max(corner[0], 0.0), max(style.width - width, 0))
    bottom = min(max(corner[1], float(height)), max(style.height - baseline, height))
    return round(left), round(bottom)


def _fixed(point: Array | Sequence[float]) -> tuple[int, int]:
    """A point near the photo in OpenCV's fixed point (``_SHIFT`` fractional bits)."""
    return round(float(point[0]) * _ONE), round(float(point[1]) * _ONE)


def _fixed_points(points: Array) -> NDArray[np.int32]:
    return np.round(np.asarray(points) * _ONE).astype(np.int32)
