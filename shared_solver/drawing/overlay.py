"""The answer drawn on a photo by OpenCV, for the phone that took it: a thin renderer of
:class:`.shapes.AnswerDrawing` (computed by :mod:`.layout`, the same shapes the phone draws
as SVG). Only the strokes' widths, the outline and the font are chosen here.

Every position stays a float until it is drawn: OpenCV takes int coordinates in 1/16 px
(``_SHIFT``), near the photo, which the shapes are by construction.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import validation
from ..errors import Reason
from ..projective import Array
from ..refusal import SolverError
from ..result import SolveResult
from .layout import Photo, answer_drawing
from .palette import (
    BAND_OPACITY,
    FRIEND_COLOUR_BGR,
    OUTLINE_COLOUR_BGR,
    SUSPECT_COLOUR_BGR,
    Bgr,
    landmark_colour,
)
from .shapes import (
    AnswerDrawing,
    ArrowShape,
    CurveShape,
    FrameShape,
    LandmarkRing,
    Point,
    Polyline,
    SightShape,
)
from .sizes import Sizes

Image = NDArray[np.uint8]

# OpenCV's fixed point: coordinates in 1/16 px place markers with sub-pixel accuracy.
_SHIFT = 4
_ONE = 1 << _SHIFT
_FONT = cv2.FONT_HERSHEY_SIMPLEX
_AA = cv2.LINE_AA

# Draws a shape in a colour, its strokes widened by the given px (0 = as designed).
_Shape = Callable[[Bgr, int], None]


@dataclass(frozen=True)
class _Style:
    """Strokes and text in px for one photo; all grow with its diagonal, so they read on a
    phone that shows the whole photo across its screen."""

    width: int
    height: int
    line: int
    outline: int
    font_scale: float
    text_thickness: int

    @classmethod
    def of(cls, sizes: Sizes) -> _Style:
        # Thin: a stroke hides what is under it. A phone shows the whole photo across its
        # screen (one screen px is about diagonal / 700 photo px): 1-2 screen px, the room
        # the frame leaves around the region.
        line = round(sizes.room)
        # That keeps numbers ~10 pt high on the phone.
        font_scale = sizes.diagonal / 1100
        return cls(
            width=sizes.width,
            height=sizes.height,
            line=line,
            outline=max(2, round(0.6 * line)),
            font_scale=font_scale,
            text_thickness=max(1, round(font_scale * 2)),
        )


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
        raise SolverError(Reason.BAD_PHOTO, detail=repr(photo))
    height, width = canvas.shape[:2]
    drawing = answer_drawing(
        result,
        photo=photo,
        size=(width, height),
        landmarks=landmarks,
        labels=names,
        epipolar_lines=epipolar_lines,
    )
    return render(canvas, drawing, photo=photo)


def render(canvas: Image, drawing: AnswerDrawing, *, photo: Photo = 2) -> Image:
    """``drawing`` painted on ``canvas`` ((H, W, 3) uint8 BGR, modified and returned): the
    friend's frame on photo 2, the sight on photo 1, drawn last, over the rest."""
    style = _Style.of(Sizes.of(drawing.width, drawing.height))
    for line in drawing.epipolar_lines:
        _draw_line(
            canvas,
            line.start,
            line.end,
            thickness=max(2, style.line // 2),
            colour=landmark_colour(line.label),
            style=style,
        )
    for ring in drawing.landmarks:
        _draw_ring(canvas, ring, style)
    for candidate in drawing.candidates:
        _draw_candidate(canvas, candidate.centre, candidate.radius, style)
    if drawing.curve is not None:
        _draw_curve(canvas, drawing.curve, style)
    if drawing.banner is not None:
        centre = np.array([style.width / 2, math.hypot(style.width, style.height) / 30])
        _centred_text(canvas, drawing.banner, centre, FRIEND_COLOUR_BGR, style)
    if drawing.arrow is not None:
        _draw_border_arrow(canvas, drawing.arrow, style)
    if photo == 1 and drawing.sight is not None:
        _draw_sight(canvas, drawing.sight, style)
    elif photo == 2 and drawing.frame is not None:
        _draw_frame(canvas, drawing.frame, style)
    return canvas


# --- input ------------------------------------------------------------------------------


def _bgr_copy(image: Any) -> Image:
    """A contiguous (H, W, 3) uint8 copy of the photo to draw on."""
    if not isinstance(image, np.ndarray) or image.dtype != np.uint8:
        raise SolverError(Reason.NOT_8_BIT)
    photo: Image = image
    if photo.ndim == 3 and photo.shape[2] == 1:
        photo = photo[:, :, 0]
    if photo.size > 0 and photo.ndim == 2:
        return np.asarray(cv2.cvtColor(np.ascontiguousarray(photo), cv2.COLOR_GRAY2BGR), np.uint8)
    if photo.size > 0 and photo.ndim == 3 and photo.shape[2] == 3:
        return photo.copy(order="C")
    raise SolverError(Reason.NOT_A_PHOTO, shape=image.shape)


def _landmarks(points: ArrayLike | None, labels: Sequence[int] | None) -> tuple[Array, list[int]]:
    if points is None:
        if labels is not None and len(labels) > 0:
            raise SolverError(Reason.LABELS_WITHOUT_POINTS)
        return np.zeros((0, 2)), []
    landmarks = validation.points(points, "points")
    if labels is None:
        return landmarks, list(range(1, len(landmarks) + 1))
    try:
        names = [int(label) for label in labels]
    except (TypeError, ValueError) as error:
        raise SolverError(Reason.LABELS_NOT_WHOLE) from error
    if len(names) != len(landmarks):
        raise SolverError(Reason.ONE_LABEL_PER_LANDMARK, counts=(len(names), len(landmarks)))
    return landmarks, names


# --- what is drawn ----------------------------------------------------------------------


def _draw_frame(canvas: Image, frame: FrameShape, style: _Style) -> None:
    """The region's outline, the brackets and the label on its leader."""
    if frame.outline:
        _draw_polylines(canvas, frame.outline, max(1, round(0.75 * style.line)), style)
    _draw_polylines(canvas, frame.brackets, style.line, style)
    (_, height), baseline = _text_size(frame.label, style)
    start, end = (np.array(p) for p in frame.leader)
    if _on_photo(start, style) and _on_photo(end, style):
        _draw_line(
            canvas, *frame.leader, thickness=style.line, colour=FRIEND_COLOUR_BGR, style=style
        )
    shift = (height + baseline) / 2
    centre = end + np.array([0.0, -shift if frame.label_above else shift])
    _centred_text(canvas, frame.label, centre, FRIEND_COLOUR_BGR, style)


def _draw_sight(canvas: Image, sight: SightShape, style: _Style) -> None:
    """A thin ring with four ticks (a gun sight), open in the middle."""

    def ring(colour: Bgr, grow: int) -> None:
        thickness = style.line + grow
        centre, radius = _fixed(sight.centre), round(sight.radius * _ONE)
        cv2.circle(canvas, centre, radius, colour, thickness, _AA, _SHIFT)
        for start, end in sight.ticks:
            cv2.line(canvas, _fixed(start), _fixed(end), colour, thickness, _AA, _SHIFT)

    _outlined(ring, FRIEND_COLOUR_BGR, style)


def _draw_candidate(canvas: Image, centre: Point, radius: float, style: _Style) -> None:
    """Another position that fits: a thin "?" circle."""

    def circle(colour: Bgr, grow: int) -> None:
        thickness = style.line + grow
        cv2.circle(canvas, _fixed(centre), round(radius * _ONE), colour, thickness, _AA, _SHIFT)

    _outlined(circle, FRIEND_COLOUR_BGR, style)
    _centred_text(canvas, "?", np.array(centre), FRIEND_COLOUR_BGR, style)


def _draw_ring(canvas: Image, ring: LandmarkRing, style: _Style) -> None:
    """A thin ring with a centre dot in its number's colour, the number beside; a suspect
    inside a red ring, number + "?". The spot itself stays visible inside the ring."""
    centre = _fixed(ring.centre)
    dot = max(1.5, 0.6 * style.line)
    colour = landmark_colour(ring.label)
    if ring.suspect:

        def red(colour: Bgr, grow: int) -> None:
            size = round(ring.suspect_radius * _ONE)
            cv2.circle(canvas, centre, size, colour, style.line + grow, _AA, _SHIFT)

        _outlined(red, SUSPECT_COLOUR_BGR, style)

    def dotted(colour: Bgr, grow: int) -> None:
        size = round(ring.radius * _ONE)
        cv2.circle(canvas, centre, size, colour, style.line + grow, _AA, _SHIFT)
        cv2.circle(canvas, centre, round((dot + grow / 2) * _ONE), colour, -1, _AA, _SHIFT)

    _outlined(dotted, colour, style)
    gap = (ring.suspect_radius if ring.suspect else ring.radius) + style.line
    text = f"{ring.label}?" if ring.suspect else str(ring.label)
    _label_beside(canvas, text, np.array(ring.centre), gap=gap, colour=colour, style=style)


def _draw_curve(canvas: Image, curve: CurveShape, style: _Style) -> None:
    """The curve the friend is on (in its band, when it has one, and the stretch the
    compasses point to three times as thick), labelled above its point nearest the photo's
    centre (or the stretch's middle)."""
    if curve.halfwidth is not None:
        _draw_band(canvas, curve.polylines, curve.halfwidth)
    _draw_polylines(canvas, curve.polylines, style.line, style)
    if curve.stretch:
        _draw_polylines(canvas, curve.stretch, 3 * style.line, style)
    if curve.label_at is not None:
        (_, height), _ = _text_size(curve.text, style)
        centre = np.array(curve.label_at) - [0.0, height]
        _centred_text(canvas, curve.text, centre, FRIEND_COLOUR_BGR, style)


def _draw_border_arrow(canvas: Image, arrow: ArrowShape, style: _Style) -> None:
    """The arrow, with its text beside it on the side with more room."""
    tip, tail = np.array(arrow.tip), np.array(arrow.tail)
    _draw_arrow(canvas, tail, tip, arrow.head, style)
    unit = np.array(arrow.direction)
    (width, height), baseline = _text_size(arrow.text, style)
    # Beside the arrow rather than behind it, so a long text still stays near the border; on
    # the side facing the middle of the photo across the arrow, where there is more room.
    middle = np.array([style.width / 2, style.height / 2])
    across = np.array([-unit[1], unit[0]])
    level = abs(unit[0]) >= abs(unit[1])
    roomier = (
        (0.0, 1.0 if tip[1] <= middle[1] else -1.0)
        if level
        else (1.0 if tip[0] <= middle[0] else -1.0, 0.0)
    )
    across = across if across @ roomier >= 0 else -across
    head_half_width = arrow.head / 2
    support = abs(across[0]) * width + abs(across[1]) * (height + baseline)
    clearance = support / 2 + head_half_width + style.line
    centre = (tip + tail) / 2 + clearance * across
    _centred_text(canvas, arrow.text, centre, FRIEND_COLOUR_BGR, style)


def _draw_arrow(canvas: Image, tail: Array, tip: Array, head: float, style: _Style) -> None:
    """A thick arrow from ``tail`` to ``tip`` with a filled triangular head ``head`` long."""
    unit = (tip - tail) / float(np.hypot(*(tip - tail)))
    across = np.array([-unit[1], unit[0]])
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


def _draw_band(canvas: Image, polylines: Sequence[Polyline], halfwidth: float) -> None:
    """A translucent friend-coloured band ``halfwidth`` px either side of the polylines."""
    fixed = [_fixed_points(np.array(line)) for line in polylines if len(line) > 1]
    if not fixed:
        return
    mask = np.zeros(canvas.shape[:2], np.uint8)
    cv2.polylines(mask, fixed, False, 255, max(1, round(2.0 * halfwidth)), cv2.LINE_8, _SHIFT)
    inside = mask > 0
    blended = canvas[inside] * (1.0 - BAND_OPACITY) + np.array(FRIEND_COLOUR_BGR) * BAND_OPACITY
    canvas[inside] = blended.astype(np.uint8)


def _draw_polylines(
    canvas: Image, polylines: Sequence[Polyline], thickness: int, style: _Style
) -> None:
    """Friend-coloured open polylines over a dark outline."""
    fixed = [_fixed_points(np.array(line)) for line in polylines if len(line) > 1]

    def strokes(colour: Bgr, grow: int) -> None:
        cv2.polylines(canvas, fixed, False, colour, thickness + grow, _AA, _SHIFT)

    if fixed:
        _outlined(strokes, FRIEND_COLOUR_BGR, style)


def _draw_line(
    canvas: Image, start: Point, end: Point, *, thickness: int, colour: Bgr, style: _Style
) -> None:
    def line(colour: Bgr, grow: int) -> None:
        cv2.line(canvas, _fixed(start), _fixed(end), colour, thickness + grow, _AA, _SHIFT)

    _outlined(line, colour, style)


def _on_photo(point: Array, style: _Style) -> bool:
    x, y = point
    return bool(0 <= x <= style.width and 0 <= y <= style.height)


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
