"""The solver's stable codes: why it refused (:class:`ErrorCode`, carried by the one
exception type it raises) and what it warns of on an answer (:class:`WarningCode`).

Every refusal carries a machine-readable ``code`` (stable: the REST API returns it and the
phones branch on it) and a ``message`` a person can act on; every warning a code, its
parameters and its sentence (``shared_solver.result.SolverWarning``).
"""

from __future__ import annotations

from enum import StrEnum
from typing import Literal


class ErrorCode(StrEnum):
    """Why the solver refused. The values are a public contract: never rename one."""

    INVALID_SHAPE = "invalid_shape"
    NOT_FINITE = "not_finite"
    MISMATCHED_LENGTHS = "mismatched_lengths"
    TOO_FEW_LANDMARKS = "too_few_landmarks"
    TOO_MANY_LANDMARKS = "too_many_landmarks"
    REPEATED_LANDMARKS = "repeated_landmarks"
    COLLINEAR_LANDMARKS = "collinear_landmarks"
    EPIPOLE_ON_LANDMARK = "epipole_on_landmark"
    LANDMARKS_ON_EPIPOLAR_LINE = "landmarks_on_epipolar_line"
    CONFLICTING_INPUTS = "conflicting_inputs"
    MISSING_EPIPOLE1 = "missing_epipole1"
    INVALID_PARAMETER = "invalid_parameter"
    DEGENERATE_CONFIGURATION = "degenerate_configuration"
    NO_SOLUTION = "no_solution"


# What each code means, in a line (docs/api.md's table of codes is generated from it).
MEANING: dict[ErrorCode, str] = {
    ErrorCode.INVALID_SHAPE: "a point is not two numbers, or a photo size not two",
    ErrorCode.NOT_FINITE: "a coordinate is NaN or infinite",
    ErrorCode.MISMATCHED_LENGTHS: "the two photos' landmark lists differ in length",
    ErrorCode.TOO_FEW_LANDMARKS: "fewer landmarks than what was marked needs",
    ErrorCode.TOO_MANY_LANDMARKS: "more landmarks than the solver takes",
    ErrorCode.REPEATED_LANDMARKS: "two landmarks tapped at the same spot",
    ErrorCode.COLLINEAR_LANDMARKS: "the landmarks lie on one line: they fix no geometry",
    ErrorCode.EPIPOLE_ON_LANDMARK: "the friend marked on a landmark",
    ErrorCode.LANDMARKS_ON_EPIPOLAR_LINE: "the landmarks lie on one line through the friend",
    ErrorCode.CONFLICTING_INPUTS: "the friend marked both as a point and as a line in photo 1",
    ErrorCode.MISSING_EPIPOLE1: "the friend marked in photo 2 without the mark in photo 1",
    ErrorCode.INVALID_PARAMETER: "a number out of what the solver honours (a sigma, a size, "
    "a lens, a coordinate beyond 1e6 px)",
    ErrorCode.DEGENERATE_CONFIGURATION: "the taps fit many geometries: no answer is honest",
    ErrorCode.NO_SOLUTION: "no geometry fits the taps",
}


class WarningCode(StrEnum):
    """What an answer warns of. The values are a public contract: never rename one."""

    CAMERA_MODEL_DISAGREES = "camera_model_disagrees"
    CAMERA_MODEL_UNSURE = "camera_model_unsure"
    ON_THE_CURVE = "on_the_curve"
    MARKS_DISAGREE = "marks_disagree"
    FAR_TO_THE_SIDE = "far_to_the_side"
    NOT_PINNED_DOWN = "not_pinned_down"
    BEHIND_YOU = "behind_you"
    OUTSIDE_PHOTO = "outside_photo"
    UNCERTAIN = "uncertain"
    MISTAPPED = "mistapped"
    MISFIT = "misfit"
    AMBIGUOUS = "ambiguous"
    NO_MARGIN = "no_margin"


# What each warning means, in a line, and its parameters (docs/api.md's table).
WARNING_MEANING: dict[WarningCode, str] = {
    WarningCode.CAMERA_MODEL_DISAGREES: "the taps fit no two phone photos: answered as any "
    "two cameras (the paper's geometry)",
    WarningCode.CAMERA_MODEL_UNSURE: "the taps barely fit two phone photos: the region is "
    "widened to hold either answer",
    WarningCode.ON_THE_CURVE: "too few landmarks for a point: the friend is on `curve`",
    WarningCode.MARKS_DISAGREE: "the taps disagree more than their precision says: the "
    "region is widened",
    WarningCode.FAR_TO_THE_SIDE: "the friend is (nearly) infinitely far to the side",
    WarningCode.NOT_PINNED_DOWN: "the taps do not fix the friend's position (nor its side "
    "of the camera)",
    WarningCode.BEHIND_YOU: "the friend is behind the camera of photo 2",
    WarningCode.OUTSIDE_PHOTO: "the friend is beyond the `side` edge of photo 2, `distance_px` px",
    WarningCode.UNCERTAIN: "the 95 % region is wider than a tenth of photo 2",
    WarningCode.MISTAPPED: "landmark `landmark` left out of the answer: `distance_px` px "
    "from where the others put it",
    WarningCode.MISFIT: "(a session's taps) landmark `landmark` of `photo` is tapped far "
    "outside its band",
    WarningCode.AMBIGUOUS: "several positions fit as well (`candidates`); what to add "
    "depends on how the friend was `marked`",
    WarningCode.NO_MARGIN: "the likeliest of several positions, with no region; what to add "
    "depends on how the friend was `marked`",
}

# The photo a warning is about, when it is one photo whatever its parameters: where the friend
# is in photo 2 (the answer's photo) is not said to the phone of photo 1, who sees them.
WARNING_PHOTO: dict[WarningCode, Literal[1, 2]] = {
    WarningCode.ON_THE_CURVE: 2,
    WarningCode.FAR_TO_THE_SIDE: 2,
    WarningCode.BEHIND_YOU: 2,
    WarningCode.OUTSIDE_PHOTO: 2,
    WarningCode.UNCERTAIN: 2,
}
# The codes whose photo is a parameter: the photo of the landmark they name. Every other code
# is about the taps as a whole, said to both phones.
WARNING_OF_ONE_PHOTO = frozenset({WarningCode.MISFIT})


class SolverError(ValueError):
    """Input the solver cannot answer honestly.

    Attributes:
        code: one of :class:`ErrorCode`, stable across versions.
        message: a plain-English sentence saying what to do about it.
    """

    def __init__(self, code: ErrorCode, message: str) -> None:
        super().__init__(message)
        self.code = code
        self.message = message

    def __repr__(self) -> str:
        return f"SolverError({self.code.value!r}, {self.message!r})"
