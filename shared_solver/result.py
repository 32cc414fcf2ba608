"""What ``solve`` returns: a pydantic model whose JSON is exactly the REST API's answer.

Pixel positions are ``[x, y]`` (x right, y down) in the photo's own pixels; homogeneous
ones ``[x, y, w]`` (unit norm, ``w == 0`` at infinity). Matrices are lists of rows.
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from . import words
from .errors import WARNING_OF_ONE_PHOTO, WARNING_PHOTO, WarningCode

Method = Literal[
    "conic",
    "five_point_epipole",
    "least_squares_epipole",
    "planar",
    "six_point_line",
    "two_epipoles",
    "seven_point",
    "eight_point",
    "pinhole_epipole",
    "pinhole_two_epipoles",
    "pinhole_line",
    "pinhole_landmarks",
    "pinhole_level",
]
CameraModel = Literal["projective", "pinhole"]
Quality = Literal["good", "fair", "poor"]
Pixel = tuple[float, float]
Homogeneous = tuple[float, float, float]
Matrix = tuple[Homogeneous, Homogeneous, Homogeneous]
Row9 = tuple[float, float, float, float, float, float, float, float, float]
Covariance9 = tuple[Row9, Row9, Row9, Row9, Row9, Row9, Row9, Row9, Row9]


class _Frozen(BaseModel):
    model_config = ConfigDict(frozen=True)


class Ellipse(_Frozen):
    """A region in photo 2: semi-axes in px, ``angle_deg`` of the first axis from x, y down."""

    center: Pixel
    axes: tuple[float, float] = Field(description="Semi-axis lengths (a >= b), px.")
    angle_deg: float = Field(description="Angle of axis a from the x axis, degrees, y down.")


class Uncertainty(_Frozen):
    """Where friend 1 is with probability ``level``, from the tap noise ``tap_sigma``."""

    level: float = 0.95
    ellipse: Ellipse | None = Field(
        description="None when the position is at infinity or not bounded by the taps."
    )
    covariance: tuple[tuple[float, float], tuple[float, float]] | None = Field(
        default=None, description="2x2 covariance of epipole2, px^2."
    )


class Candidate(_Frozen):
    """One geometry that fits the landmarks exactly (several for a line or 7 landmarks)."""

    rank: int = Field(description="1 = most plausible.")
    epipole1: Pixel | None
    epipole1_h: Homogeneous
    epipole2: Pixel | None
    epipole2_h: Homogeneous
    fundamental: Matrix
    oriented_violations: int = Field(
        description="Landmarks that would have to be behind a camera (0 for a real scene)."
    )
    focal_lengths: tuple[float | None, float | None] = Field(
        description="Focal lengths (px) the geometry implies, None if imaginary."
    )
    phone_like: bool


class CameraEstimate(_Frozen):
    """One photo's camera: what was known about it, and the focal length the answer used."""

    known: Literal["unknown", "phone", "known_focal"] = Field(
        description="What the caller said about this camera (Camera.kind)."
    )
    focal_px: float | None = Field(
        description="Focal length in px the answer used or estimated; None for the "
        "projective model, which has none."
    )
    focal_35mm: float | None = Field(description="The same as a 35 mm-equivalent, mm.")
    focal_35mm_sd: float | None = Field(
        description="Its standard deviation after the fit, mm (how well the taps and the "
        "prior pin it down)."
    )


class SolverWarning(_Frozen):
    """Something to check or do about an answer: a stable ``code`` (docs/api.md lists them),
    its parameters, and its sentence (``message``, made from the two by ``words.warning``).
    A phone is told it by the photo it is about, never by its sentence."""

    code: WarningCode
    photo: Literal[1, 2] | None = Field(
        None,
        description="The photo it is about, said only to that photo's phone (2: where the "
        "friend is in the answer's photo); null: the taps as a whole, said to both.",
    )
    landmark: int | None = Field(None, description="The landmark's number (#3).")
    distance_px: float | None = Field(
        None,
        description="mistapped: how far the landmark is from where the others put it; "
        "outside_photo: how far beyond the photo's edge the friend is, px.",
    )
    side: words.Side | None = Field(None, description="The edge of the photo the friend is past.")
    marked: words.Marked | None = Field(
        None, description="How the friend was marked in photo 1: what would decide."
    )
    message: str = Field(description="The sentence a person reads.")

    @classmethod
    def of(
        cls,
        code: WarningCode,
        *,
        photo: Literal[1, 2] | None = None,
        landmark: int | None = None,
        distance_px: float | None = None,
        side: words.Side | None = None,
        marked: words.Marked | None = None,
    ) -> SolverWarning:
        """The warning ``code`` with these parameters and its sentence; about ``photo``, or
        the photo the code is always about (``errors.WARNING_PHOTO``).

        Raises:
            ValueError: a parameter the code's sentence names is missing, or the photo of a
                code about one photo.
        """
        if photo is None and code in WARNING_OF_ONE_PHOTO:
            raise ValueError(f"the warning {code.value!r} is about one photo: name it")
        return cls(
            code=code,
            photo=photo or WARNING_PHOTO.get(code),
            landmark=landmark,
            distance_px=distance_px,
            side=side,
            marked=marked,
            message=words.warning(
                code, landmark=landmark, distance_px=distance_px, side=side, marked=marked
            ),
        )

    def told_to(self, photo: Literal[1, 2]) -> bool:
        """Whether the phone of ``photo`` is told it: everything not about the other photo."""
        return self.photo in (None, photo)


class SolveResult(_Frozen):
    """Where friend 1 stands in friend 2's photo, how sure that is, and why."""

    method: Method
    camera_model: CameraModel = Field(
        "projective",
        description="'pinhole': solved with what a phone camera is (square pixels, centred, "
        "a focal length prior); 'projective': any two cameras, as in the paper.",
    )
    cameras: list[CameraEstimate] = Field(
        default_factory=list,
        description="Photo 1's and photo 2's camera, when cameras were given.",
    )
    landmark_count: int
    tap_sigma: float = Field(description="The typical tap's standard deviation, px (rms).")
    epipole2: Pixel | None = Field(
        description="Friend 1 in photo 2 (the answer), px; None at infinity or for a conic."
    )
    epipole2_h: Homogeneous | None
    epipole1: Pixel | None = Field(description="Friend 2 in photo 1, refined from the tap.")
    epipole1_h: Homogeneous | None
    fundamental: Matrix | None = None
    fundamental_covariance: Covariance9 | None = Field(
        default=None,
        description="9x9 first-order covariance of `fundamental` read row by row (F at unit "
        "norm), widened as the region is when the taps disagree; what an epipolar line's "
        "uncertainty is computed from (shared_solver.matching). Only when asked "
        "(solve(..., fundamental_covariance=True)); None for the plane model, the curve of "
        "four landmarks, and answers that list several candidates.",
    )
    homography: Matrix | None = Field(default=None, description="Plane model: q ~ H p.")
    conic2: Matrix | None = Field(default=None, description="4 landmarks: e2^T C e2 = 0.")
    curve2: list[list[Pixel]] | None = Field(
        default=None,
        description="No landmark, both phones' gravity (method 'pinhole_level'): the level "
        "friend 1 stands on in photo 2, as the pieces of it inside the photo, each a "
        "polyline of [x, y] px within 0.25 px of the curve (at the priors' focal lengths).",
    )
    curve2_halfwidth: float | None = Field(
        default=None,
        description="The 95 % half-width of the band around `curve2`, px (its median along "
        "the visible curve); None when no piece of the curve is inside the photo.",
    )
    curve2_stretch: list[list[Pixel]] | None = Field(
        default=None,
        description="No landmark, both phones' gravity and compass headings: the stretch of "
        "`curve2` the headings point to (their 95 % range of turns), as the pieces of it "
        "inside the photo. A hint: steel bends compasses, and no landmark checks them. None "
        "without headings, or when that stretch is outside the photo.",
    )
    used_gravity: bool = Field(
        default=False,
        description="Both phones' gravity at the shutter entered the answer (gravity1, "
        "gravity2); False when none was given, or when it contradicted the landmarks "
        "(warning 'gravity_disagrees').",
    )
    used_heading: bool = Field(
        default=False,
        description="Both phones' compass headings at the shutter entered the answer "
        "(heading1, heading2, with both gravity readings); False when not given, or when "
        "the landmarks contradicted them (warning 'heading_disagrees').",
    )
    candidates: list[Candidate] = Field(default_factory=list)
    uncertainty: Uncertainty | None = None
    suspect_landmarks: list[int] = Field(
        default_factory=list,
        description="Indices (0-based, input order) of landmarks that look mis-tapped; "
        "the answer is computed without them.",
    )
    residuals: list[float] = Field(
        default_factory=list,
        description="Per landmark (input order), its distance from the fitted geometry, px.",
    )
    quality: Quality
    warnings: list[SolverWarning] = Field(default_factory=list)
