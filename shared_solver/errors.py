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
