"""The one exception type the solver raises, with its stable codes.

Every refusal carries a machine-readable ``code`` (stable: the REST API returns it and the
phones branch on it) and a ``message`` a person can act on.
"""

from __future__ import annotations

from enum import StrEnum


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
