"""What a phone sends as its taps (each PUT replaces the whole set): the landmarks, and the
friend if this phone can see them, each tap with how precise it is."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, Strict

from backend.limits import MAX_LANDMARK_ID
from backend.participants import Role
from shared_solver.drawing.shapes import AnswerDrawing
from shared_solver.matching.band import BandShape
from shared_solver.refusal import Refusal
from shared_solver.result import Ellipse, SolverWarning

from .photo_order import PhotoOrder

# A JSON number, nothing that converts to one ("12", true): a tap sent as anything else is
# a bug of the client, refused rather than guessed at.
Coordinate = Annotated[float, Strict()]
# A tap's standard deviation in stored-photo px, per axis: how far the finger may be off at
# the zoom it tapped at (docs/app.md). Missing: the server's BUDDY_TAP_SIGMA.
Sigma = Annotated[float, Strict(), Field(gt=0.0, le=1000.0)]


class Mark(BaseModel):
    """A point tapped on the photo."""

    model_config = ConfigDict(allow_inf_nan=False, extra="forbid")

    x: Coordinate = Field(description="Stored-photo pixels, x right.")
    y: Coordinate = Field(description="Stored-photo pixels, y down.")
    sigma: Sigma | None = Field(
        None, description="How precise the tap is: its standard deviation per axis, px."
    )


class Landmark(Mark):
    """A landmark: a spot both friends tap, #3 here being #3 there."""

    id: int = Field(
        ge=1,
        le=MAX_LANDMARK_ID,
        strict=True,
        description="The number people see; #3 here is #3 there.",
    )


class FriendLine(BaseModel):
    """'My friend is somewhere along here': the line ``a x + b y + c = 0`` through them."""

    model_config = ConfigDict(allow_inf_nan=False, extra="forbid")

    a: Coordinate
    b: Coordinate
    c: Coordinate
    sigma: Sigma | None = Field(
        None, description="How precise the line is across it: a standard deviation, px."
    )


class Taps(BaseModel):
    """A phone's whole tap set (each PUT replaces it)."""

    model_config = ConfigDict(
        allow_inf_nan=False,
        extra="forbid",
        json_schema_extra={
            "examples": [
                {
                    "landmarks": [
                        {"id": 1, "x": 412.0, "y": 230.5, "sigma": 6.0},
                        {"id": 2, "x": 1830.0, "y": 402.0, "sigma": 2.5},
                        {"id": 3, "x": 960.0, "y": 1410.0, "sigma": 6.0},
                    ],
                    "friend": {"x": 1204.0, "y": 861.0, "sigma": 2.0},
                }
            ]
        },
    )

    landmarks: list[Landmark] = Field(default_factory=list)
    friend: Mark | None = Field(
        None, description="Where your friend is in your photo, if you can see them."
    )
    friend_line: FriendLine | None = Field(
        None,
        description="Instead of friend: a line through your friend in your photo, when you "
        "can only say 'somewhere along here'.",
    )


class LandmarkBand(BandShape):
    """Where a landmark the other phone tapped must be in this photo, once there is an
    answer: its epipolar line widened by the answer's uncertainty (docs/geometry.md)."""

    id: int = Field(description="The landmark's number.")


class FriendInPhoto(BaseModel):
    """Where the friend is in one phone's photo, and how that is known."""

    friend: tuple[float, float] | None = Field(
        None,
        description="Where your friend is in your photo, px; None when they are behind you, "
        "infinitely far to the side, or known only to be on a curve.",
    )
    friend_h: tuple[float, float, float] | None = Field(
        None,
        description="The same, homogeneous and oriented: w > 0 in front of the camera, w < 0 "
        "behind it (turn around), w = 0 a direction.",
    )
    how: Literal["marked", "on_line", "solved"] = Field(
        description="'marked': you tapped your friend (refined by the fit); 'on_line': the "
        "point of your line the fit chose; 'solved': found from your friend's mark and the "
        "landmarks."
    )
    region: Ellipse | None = Field(
        None, description="Where your friend is with 95 % probability, when that is known."
    )
    curve: tuple[tuple[float, float, float], ...] | None = Field(
        None,
        description="Too few landmarks for a point: your friend is on this conic "
        "(x, y, 1) C (x, y, 1)^T = 0.",
    )
    level: list[list[tuple[float, float]]] | None = Field(
        None,
        description="No landmark yet, both phones' gravity: your friend is on this level "
        "of the venue, the pieces of its curve inside your photo (px); how far either "
        "side of it is `level_halfwidth`.",
    )
    level_halfwidth: float | None = Field(
        None, description="The 95 % half-width of the band around `level`, px."
    )
    level_stretch: list[list[tuple[float, float]]] | None = Field(
        None,
        description="No landmark yet, both phones' gravity and compass headings: the "
        "stretch of `level` the compasses point to, px. A hint: steel bends compasses.",
    )
    candidates: list[tuple[float, float]] = Field(
        default_factory=list, description="Other positions that fit the taps as well."
    )
    focal_35mm: float | None = Field(
        None, description="The focal length of your photo's lens the answer used, 35 mm mm."
    )
    focal_px: float | None = Field(
        None,
        description="The same in your photo's px (principal point at its centre): what "
        'carries a pixel of your photo into a direction, as "Show me" does.',
    )
    warnings: list[SolverWarning] = Field(
        default_factory=list,
        description="What to check or do next, said to you: the warnings about your photo "
        "or about both, each a code, its parameters and its sentence (message).",
    )
    bands: list[LandmarkBand] = Field(
        default_factory=list,
        description="For each landmark only your friend has tapped: where it must be in "
        "your photo.",
    )
    misfits: list[int] = Field(
        default_factory=list,
        description="Your landmarks tapped far outside their band: they do not fit the "
        "others (check them).",
    )
    drawing: AnswerDrawing | None = Field(
        None,
        description="What to draw of the answer on your photo, px: the frame, the curve, "
        "the arrow at the border (the overlay draws the same).",
    )


class Answer(BaseModel):
    """What each phone is told, from both phones' taps (``in_photo``: by whose photo)."""

    method: str = Field(description="The solver's method (docs/solver.md).")
    camera_model: Literal["projective", "pinhole"] = Field(
        description="'pinhole': solved as two phone cameras; 'projective': as any two "
        "cameras, because the taps did not fit two phone photos."
    )
    quality: Literal["good", "fair", "poor"]
    landmark_ids: list[int] = Field(description="The landmarks in both photos, used in order.")
    suspects: list[int] = Field(
        default_factory=list,
        description="Landmarks that look mis-tapped, left out of the answer: re-check them.",
    )
    residuals: list[float] = Field(
        default_factory=list,
        description="Per landmark of landmark_ids, its distance from the fitted geometry, px.",
    )
    used_heading: bool = Field(
        False,
        description="Both phones' compass headings entered the answer (beside both phones' "
        "gravity); False without them, or when the landmarks contradicted them (warning "
        "'heading_disagrees').",
    )
    in_photo: dict[Role, FriendInPhoto]


class StoredAnswer(BaseModel):
    """The answer as the sessions table keeps it (JSON), for the version it was computed
    for: what each phone is told, the solver's own answer and whose photo was its photo 1;
    or why there is none (the solver's refusal, worded for a script: each phone is told it
    again from its reason and parameters, ``Refusal.said_to``).

    ``solution`` stays the solver's JSON until it is used (the overlay, a known fit, a
    suggested spot): every read of a phone's state would otherwise validate it again.
    """

    answer: Answer | None = None
    solution: dict[str, Any] | None = None
    first: Role | None = None
    error: Refusal | None = None

    @classmethod
    def read(cls, stored: dict[str, Any] | None) -> StoredAnswer | None:
        """The answer as the storage layer hands it (parsed JSON; None: none yet)."""
        return None if stored is None else cls.model_validate(stored)

    @property
    def order(self) -> PhotoOrder | None:
        """Whose photo was the solver's photo 1 (``first``, as stored); None: no answer."""
        return None if self.first is None else PhotoOrder(self.first)

    def as_json(self) -> dict[str, Any]:
        return self.model_dump(mode="json")


class Reanchored(BaseModel):
    """How your phone has turned since your photo, from one frame of its live view matched to
    the photo (``shared_solver.matching.reanchor``): what "Show me" resets its gyroscope's
    drift with."""

    rotation: list[list[float]] = Field(
        description="3 x 3, row by row: takes a direction in the photo's camera frame (x right "
        "along its rows, y down its columns, z out of the lens) to the frame's.",
        examples=[[[0.9986, 0.0, 0.0523], [0.0, 1.0, 0.0], [-0.0523, 0.0, 0.9986]]],
    )
    frame_focal_px: float = Field(description="The frame's focal length, px of the frame sent.")
    inliers: int = Field(description="Features of the frame that fit the turn.")
    degrees: float = Field(description="How far the phone has turned since the photo.")


class Spot(BaseModel):
    """A point of a photo, px (x right, y down)."""

    x: float
    y: float


class LandmarkSuggestion(BaseModel):
    """A suggested spot for a landmark your friend tapped and you have not: their photo's
    patch found along the landmark's band in your photo, shown only when the match is sure
    (docs/suggestions.md)."""

    id: int = Field(description="The landmark's number.")
    answer_version: int = Field(description="The answer the search used (its band).")
    spot: Spot | None = Field(
        examples=[{"x": 1412.5, "y": 630.0}, None],
        description="Where to tap, px of your photo; null: no sure match, find it by eye.",
    )


class TapsChanged(BaseModel):
    """Event ``taps``: a phone replaced its taps; the answer of the version before goes
    (event ``answer`` brings the new one, often in the same breath)."""

    role: Role = Field(description="Whose taps.")
    version: int = Field(description="The session's version this change made.")
    taps: Taps = Field(description="Their taps now.")
    landmarks_needed: int | None = Field(
        description="As the state says it at this version, before its answer. Null: another "
        "change came in between, so this event cannot tell it: fetch the state."
    )


class AnswerChanged(BaseModel):
    """Event ``answer``: the answer for a version, as the state then shows it."""

    version: int = Field(description="The version it answers.")
    answer: Answer | None = Field(description="As the state's answer (both phones' parts).")
    answer_error: dict[Role, Refusal] | None = Field(
        description="Why there is no answer (its code, reason, parameters and message), said "
        "to each phone: answer_error[you] is the state's answer_error."
    )
    landmarks_needed: int = Field(description="As the state says it with this answer.")
