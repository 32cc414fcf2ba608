"""What is drawn of an answer on one photo (:class:`.shapes.AnswerDrawing`), computed once
for both renderers: the OpenCV overlay (:mod:`.overlay`) and the phone's SVG layer.

The friend must stay visible: nothing is drawn on the spot where they are. Photo 2 (the
photo the friend was found in) gets an open frame: corner brackets around the 95 % region
(never smaller than a person far across a hall), the region's outline thin inside them, and
"friend" on a short leader beside; an arrow at the border when the friend is outside the
photo or at infinity; the curve the friend is on, labelled, when only 4 landmarks were
marked and the cameras are unknown. Photo 1 (the photo the friend was tapped in) gets the
tapped friend as a sight open in the middle. Both get the landmarks as thin rings with a
centre dot, their numbers beside them, and mis-tap suspects ringed in red (docs/app.md).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Literal

import numpy as np

from .. import words
from ..projective import Array, to_pixel
from ..result import Homogeneous, Pixel, SolveResult
from . import arrow
from .curves import clip_line, conic_polylines
from .frame import frame, frame_box, sight
from .shapes import (
    AnswerDrawing,
    Box,
    CandidateRing,
    CurveShape,
    EpipolarLineShape,
    LandmarkRing,
    Polyline,
)
from .sizes import SUSPECT_RING, Sizes

# Which photo of the answer this is: 1, the friend was tapped in it (epipole1); 2, the
# friend was found in it (epipole2).
Photo = Literal[1, 2]


def answer_drawing(
    result: SolveResult,
    *,
    photo: Photo,
    size: tuple[int, int],
    landmarks: Array | None = None,
    labels: Sequence[int] = (),
    epipolar_lines: bool = False,
) -> AnswerDrawing:
    """The answer's shapes on photo ``photo`` (1 or 2) of ``size`` (width, height) px.

    ``landmarks`` (N, 2) px are this photo's, in the order given to ``solve`` (the indices
    of ``result.suspect_landmarks`` refer to it), ``labels`` their numbers. With
    ``epipolar_lines``, each landmark's line through the friend's position (also when that
    is at infinity). See :func:`.overlay.draw_overlay` for what each shape means.
    """
    width, height = size
    sizes = Sizes.of(width, height)
    points = np.zeros((0, 2)) if landmarks is None else np.asarray(landmarks, np.float64)
    ellipse = result.uncertainty.ellipse if result.uncertainty is not None else None
    if photo == 2:
        friend, friend_h = result.epipole2, result.epipole2_h
        others = [c.epipole2 for c in result.candidates]
    else:
        friend, friend_h = result.epipole1, result.epipole1_h
        others = [c.epipole1 for c in result.candidates]
        ellipse = None
    drawing: dict[str, object] = {
        "width": width,
        "height": height,
        "person": sizes.frame_half,
        "landmarks": _rings(points, labels, set(result.suspect_landmarks), sizes),
        "candidates": _candidates(others, friend, sizes),
    }
    if friend is not None and all(map(math.isfinite, friend)):
        half, _ = frame_box(ellipse, sizes)
        drawing["focus"] = Box(centre=friend, half=(float(half[0]), float(half[1])))
    if epipolar_lines and friend_h is not None:
        drawing["epipolar_lines"] = _epipolar_lines(np.array(friend_h), points, labels, sizes)
    if photo == 2 and result.conic2 is not None:
        drawing["curve"] = _curve(
            conic_polylines(np.array(result.conic2), sizes.width, sizes.height), sizes
        )
    if photo == 2 and result.curve2 is not None:
        drawing["curve"] = _curve(
            result.curve2, sizes, result.curve2_halfwidth, result.curve2_stretch
        )
    if friend is None and friend_h is not None and _behind(friend_h):
        # Behind the camera: no point of this photo is right. Say so, as solve's warning does.
        pinned = result.quality != "poor"
        drawing["banner"] = words.DRAWN_BEHIND if pinned else words.DRAWN_UNCLEAR
    elif _inside(friend, sizes):
        at = np.array(friend)
        drawing["frame"] = frame(at, ellipse, sizes)
        if photo == 1:
            drawing["sight"] = sight(at, sizes)
    else:
        drawing["arrow"] = arrow.towards(friend, friend_h, sizes)
    return AnswerDrawing.model_validate(drawing)


def _inside(friend: Pixel | None, sizes: Sizes) -> bool:
    return (
        friend is not None and all(map(math.isfinite, friend)) and sizes.contains(np.array(friend))
    )


def _behind(homogeneous: Homogeneous) -> bool:
    """An oriented position with ``w < 0`` that is not at infinity: behind the camera."""
    return homogeneous[2] < 0 and to_pixel(np.array(homogeneous)) is not None


def _curve(
    polylines: Sequence[Polyline],
    sizes: Sizes,
    halfwidth: float | None = None,
    stretch: Sequence[Polyline] | None = None,
) -> CurveShape:
    """The curve's pieces (each [(x, y), ...] px), and its label above its point nearest the
    photo's centre (above its band, when it has one), or nearest the middle of the stretch
    the compasses point to."""
    hinted = [p for line in stretch or [] for p in line]
    points = np.array(hinted or [p for line in polylines for p in line]).reshape(-1, 2)
    label_at = None
    if len(points):
        nearest = points[np.argmin(np.hypot(*(points - sizes.centre).T))]
        label_at = (float(nearest[0]), float(nearest[1] - sizes.margin - (halfwidth or 0.0)))
    return CurveShape(
        polylines=list(polylines),
        label_at=label_at,
        text=words.DRAWN_ON_CURVE
        if halfwidth is None
        else words.DRAWN_ON_LEVEL
        if not stretch
        else words.DRAWN_COMPASS_HINT,
        halfwidth=halfwidth,
        stretch=None if not stretch else list(stretch),
    )


def _rings(
    points: Array, labels: Sequence[int], suspects: set[int], sizes: Sizes
) -> list[LandmarkRing]:
    """The landmarks on (or just beside) the photo."""
    return [
        LandmarkRing(
            centre=(float(point[0]), float(point[1])),
            radius=sizes.landmark_radius,
            label=label,
            suspect=index in suspects,
            suspect_radius=SUSPECT_RING * sizes.landmark_radius,
        )
        for index, (point, label) in enumerate(zip(points, labels, strict=True))
        if sizes.contains(point, pad=sizes.margin)
    ]


def _candidates(
    others: list[Pixel | None], friend: Pixel | None, sizes: Sizes
) -> list[CandidateRing]:
    """Other positions that fit the landmarks exactly and are on the photo."""
    found = []
    for other in others:
        if other is None or not all(map(math.isfinite, other)):
            continue
        at = np.array(other)
        # The answer is refined from one of them: that one is in the frame already.
        if friend is not None and np.hypot(*(at - np.array(friend))) < sizes.frame_half:
            continue
        if sizes.contains(at):
            found.append(
                CandidateRing(centre=(float(at[0]), float(at[1])), radius=0.7 * sizes.marker_radius)
            )
    return found


def _epipolar_lines(
    epipole: Array, points: Array, labels: Sequence[int], sizes: Sizes
) -> list[EpipolarLineShape]:
    """Each landmark's epipolar line: the line through it and the epipole (maybe at infinity)."""
    lines = []
    for point, label in zip(points, labels, strict=True):
        segment = clip_line(np.cross(np.append(point, 1.0), epipole), sizes.width, sizes.height)
        if segment is not None:
            start, end = segment
            lines.append(
                EpipolarLineShape(
                    start=(float(start[0]), float(start[1])),
                    end=(float(end[0]), float(end[1])),
                    label=label,
                )
            )
    return lines
