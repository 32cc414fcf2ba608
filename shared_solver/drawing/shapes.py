"""What is drawn of the answer on one photo, as plain shapes in that photo's pixels.

Computed once (:func:`.layout.answer_drawing`) and rendered twice: by OpenCV on the photo
(:mod:`.overlay`) and by the phone as SVG over its own photo (``frontend/src/components/
AnswerLayer.tsx``, from the state's JSON). The renderers choose only stroke widths and font
sizes; where the frame, the curve and the arrow go is said here. Every coordinate is
finite and in stored-photo px (x right, y down), clipped to the photo where it is a stroke.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, PlainSerializer

# Drawn coordinates go to the phones at 0.01 px: a hundredth of the finest stroke, and the
# JSON of an answer's drawing half as long as at full precision (it rides on every answer's
# event, on a venue's slow link). The answer itself (``friend``, ``region``) keeps its
# precision. A session's overlay renders the shapes as stored (these 0.01 px: the phone's);
# :func:`.overlay.draw_overlay` renders them as computed, unrounded.
Px = Annotated[float, PlainSerializer(lambda value: round(value, 2), when_used="json")]
Point = tuple[Px, Px]
Polyline = list[Point]


class _Shape(BaseModel):
    model_config = ConfigDict(frozen=True, allow_inf_nan=False)


class Box(_Shape):
    """A box in photo px: its centre and half-sizes."""

    centre: Point
    half: Point


class FrameShape(_Shape):
    """The open frame around the friend: four corner brackets around their 95 % region
    (never smaller than a person far across a hall), the region's outline inside when it is
    larger than a person, and a label on a short leader above the frame (else below)."""

    centre: Point = Field(description="Where the friend is, px.")
    half: Point = Field(description="Half the frame's width and height, px.")
    brackets: list[Polyline] = Field(
        description="Four corner brackets, each an L: arm end, corner, arm end, px."
    )
    outline: list[Polyline] = Field(
        default_factory=list,
        description="The 95 % region's outline, clipped to the photo; empty when the region "
        "is no larger than a person (the brackets frame it) or unknown.",
    )
    sure: bool = Field(description="A 95 % region is known ('friend'), else a likely spot.")
    label: str = Field(description="'friend' or 'friend?'.")
    label_above: bool = Field(
        description="The label goes above the frame (there is room); else below it."
    )
    leader: tuple[Point, Point] = Field(
        description="The leader from the frame's edge (first) towards the label, px."
    )


class SightShape(_Shape):
    """A ring with four ticks on the tapped friend (photo 1), open in the middle."""

    centre: Point
    radius: Px = Field(description="The ring's radius, px.")
    ticks: list[tuple[Point, Point]] = Field(description="Four ticks, each (start, end), px.")


class ArrowShape(_Shape):
    """An arrow at the photo's border, on the ray from its centre towards a friend out of
    the photo (or at infinity that way)."""

    tail: Point
    tip: Point = Field(description="Where it points, inset from the border, px.")
    direction: Point = Field(description="Unit vector from the photo's centre to the friend.")
    head: Px = Field(description="The head's length (and width), px.")
    text: str = Field(description="What it says: 'friend N px off', 'friend far off this way'.")


class CurveShape(_Shape):
    """The curve the friend is on (4 landmarks, cameras unknown; or no landmark and both
    phones' gravity: their level), clipped to the photo."""

    polylines: list[Polyline] = Field(
        description="Its visible pieces, points at most ~1.4 px apart before simplification "
        "(within 0.25 px of the curve)."
    )
    label_at: Point | None = Field(
        description="Where its label goes: above the curve's point nearest the photo's centre."
    )
    text: str
    halfwidth: Px | None = Field(
        default=None,
        description="The band's 95 % half-width around the curve, px, drawn as a "
        "translucent band; None: a curve without one.",
    )
    stretch: list[Polyline] | None = Field(
        default=None,
        description="The part of the curve both phones' compasses point to (their 95 % "
        "range), drawn over the band, bolder: a hint, as steel bends compasses. None "
        "without compass headings, or when that part is outside the photo.",
    )


class LandmarkRing(_Shape):
    """A landmark: a thin ring with a centre dot in its number's colour, the number beside;
    a mis-tap suspect has a red ring around it too."""

    centre: Point
    radius: Px
    label: int = Field(description="The number people see.")
    suspect: bool
    suspect_radius: Px


class CandidateRing(_Shape):
    """Another position that fits the taps as well: a thin circle with '?'."""

    centre: Point
    radius: Px


class EpipolarLineShape(_Shape):
    """A landmark's epipolar line through this photo (drawn on request only)."""

    start: Point
    end: Point
    label: int


class AnswerDrawing(_Shape):
    """Everything drawn of the answer on one photo, in drawing order (the friend last)."""

    width: int = Field(description="The photo's size, px.")
    height: int
    person: Px = Field(
        description="How tall a person far across a hall is in this photo, px: the frame's "
        "least half-size, and the unit the phone states the region's size in."
    )
    focus: Box | None = Field(
        None,
        description="The frame's box around the friend, also when they are outside the "
        "photo (not clipped to it): what the phone brings into view.",
    )
    frame: FrameShape | None = Field(
        None, description="The frame around the friend, when they are inside the photo."
    )
    sight: SightShape | None = Field(
        None, description="Photo 1's sight on the tapped friend (the overlay draws it)."
    )
    arrow: ArrowShape | None = Field(
        None, description="The arrow at the border, when the friend is out of the photo."
    )
    curve: CurveShape | None = None
    banner: str | None = Field(
        None, description="Instead of a position: 'friend is behind you' and the like."
    )
    landmarks: list[LandmarkRing] = Field(default_factory=list)
    candidates: list[CandidateRing] = Field(default_factory=list)
    epipolar_lines: list[EpipolarLineShape] = Field(default_factory=list)
