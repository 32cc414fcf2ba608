"""Every refusal of the service, by stable code, with the one HTTP status of each code.

Domain code raises :class:`RefusedError` with an :class:`ErrorCode` and a sentence a person can
act on; it knows nothing of HTTP. The API layer (:mod:`backend.api.errors`) answers it as
``{"error": {"code": "...", "message": "..."}}`` with the status :data:`STATUS` gives the
code: one code, one status, everywhere (a test checks that the OpenAPI schema agrees).
The solver's own codes (:class:`shared_solver.ErrorCode`) are all 422.
"""

from __future__ import annotations

from enum import StrEnum


class ErrorCode(StrEnum):
    """What phones and scripts branch on. Never renamed: a new meaning gets a new code."""

    # the request itself
    BAD_REQUEST = "bad_request"
    INVALID_REQUEST = "invalid_request"
    NOT_FOUND = "not_found"
    METHOD_NOT_ALLOWED = "method_not_allowed"
    BODY_TOO_LARGE = "body_too_large"
    # who is asking
    UNAUTHORIZED = "unauthorized"
    FORBIDDEN = "forbidden"
    # pairing
    SESSION_NOT_FOUND = "session_not_found"
    INVALID_JOIN_CODE = "invalid_join_code"
    TOO_MANY_ATTEMPTS = "too_many_attempts"
    BUSY = "busy"
    # photos
    EMPTY_PHOTO = "empty_photo"
    INVALID_PHOTO = "invalid_photo"
    PHOTO_TOO_LARGE = "photo_too_large"
    UNSUPPORTED_MEDIA_TYPE = "unsupported_media_type"
    HEIC_UNSUPPORTED = "heic_unsupported"
    PHOTO_NOT_FOUND = "photo_not_found"
    # taps
    PHOTO_MISSING = "photo_missing"
    TOO_MANY_LANDMARKS = "too_many_landmarks"
    DUPLICATE_LANDMARK = "duplicate_landmark"
    OUTSIDE_PHOTO = "outside_photo"
    INVALID_LINE = "invalid_line"
    CONFLICTING_INPUTS = "conflicting_inputs"
    NOT_YOUR_MARK = "not_your_mark"
    LANDMARK_NOT_FOUND = "landmark_not_found"
    # answers
    NO_RESULT = "no_result"
    # the service
    DATABASE_UNAVAILABLE = "database_unavailable"
    INTERNAL_ERROR = "internal_error"


STATUS: dict[ErrorCode, int] = {
    ErrorCode.BAD_REQUEST: 400,
    ErrorCode.INVALID_REQUEST: 422,
    ErrorCode.NOT_FOUND: 404,
    ErrorCode.METHOD_NOT_ALLOWED: 405,
    ErrorCode.BODY_TOO_LARGE: 413,
    ErrorCode.UNAUTHORIZED: 401,
    ErrorCode.FORBIDDEN: 403,
    ErrorCode.SESSION_NOT_FOUND: 404,
    ErrorCode.INVALID_JOIN_CODE: 404,
    ErrorCode.TOO_MANY_ATTEMPTS: 429,
    ErrorCode.BUSY: 503,
    ErrorCode.EMPTY_PHOTO: 422,
    ErrorCode.INVALID_PHOTO: 422,
    ErrorCode.PHOTO_TOO_LARGE: 413,
    ErrorCode.UNSUPPORTED_MEDIA_TYPE: 415,
    ErrorCode.HEIC_UNSUPPORTED: 415,
    ErrorCode.PHOTO_NOT_FOUND: 404,
    ErrorCode.PHOTO_MISSING: 409,
    ErrorCode.TOO_MANY_LANDMARKS: 422,
    ErrorCode.DUPLICATE_LANDMARK: 422,
    ErrorCode.OUTSIDE_PHOTO: 422,
    ErrorCode.INVALID_LINE: 422,
    ErrorCode.CONFLICTING_INPUTS: 422,
    ErrorCode.NOT_YOUR_MARK: 422,
    ErrorCode.LANDMARK_NOT_FOUND: 404,
    ErrorCode.NO_RESULT: 409,
    ErrorCode.DATABASE_UNAVAILABLE: 503,
    ErrorCode.INTERNAL_ERROR: 500,
}


class RefusedError(Exception):
    """The service will not do what was asked: a stable ``code`` and a ``message`` to
    show. ``retry_after``: seconds until trying again may succeed (a limit)."""

    def __init__(self, code: ErrorCode, message: str, *, retry_after: int | None = None) -> None:
        super().__init__(message)
        self.code = code
        self.message = message
        self.retry_after = retry_after

    @property
    def status(self) -> int:
        return STATUS[self.code]
