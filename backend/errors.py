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


# What each code means, in a line: docs/api.md's table of codes is generated from it
# (python -m docsgen.error_codes; tests/test_docs_generated.py checks the committed copy).
MEANING: dict[ErrorCode, str] = {
    ErrorCode.BAD_REQUEST: "the request could not be read (a body that is not JSON, a bad header)",
    ErrorCode.INVALID_REQUEST: "a field is missing, of the wrong type or out of its range",
    ErrorCode.NOT_FOUND: "no such address",
    ErrorCode.METHOD_NOT_ALLOWED: "the address does not take that method",
    ErrorCode.BODY_TOO_LARGE: "the body is larger than the service takes",
    ErrorCode.UNAUTHORIZED: "no token, or one that opens no session",
    ErrorCode.FORBIDDEN: "the token opens another session",
    ErrorCode.SESSION_NOT_FOUND: "the session ended or never was",
    ErrorCode.INVALID_JOIN_CODE: "no search waits for that join code (wrong, used or expired)",
    ErrorCode.TOO_MANY_ATTEMPTS: "too many wrong join codes; `Retry-After` says when to try again",
    ErrorCode.BUSY: "too many searches are starting at once; try again",
    ErrorCode.EMPTY_PHOTO: "the upload has no bytes",
    ErrorCode.INVALID_PHOTO: "the upload is not a photo the service can read",
    ErrorCode.PHOTO_TOO_LARGE: "the photo is larger than the service takes",
    ErrorCode.UNSUPPORTED_MEDIA_TYPE: "not a JPEG, PNG, WebP or HEIC/HEIF file",
    ErrorCode.HEIC_UNSUPPORTED: "a HEIC/HEIF photo this service cannot decode; send a JPEG",
    ErrorCode.PHOTO_NOT_FOUND: "that phone has not uploaded a photo yet",
    ErrorCode.PHOTO_MISSING: "taps sent before your photo: upload it first",
    ErrorCode.TOO_MANY_LANDMARKS: "more landmarks than a search takes",
    ErrorCode.DUPLICATE_LANDMARK: "two landmarks with the same number",
    ErrorCode.OUTSIDE_PHOTO: "a tap outside the photo",
    ErrorCode.INVALID_LINE: "the line through the friend does not cross the photo",
    ErrorCode.CONFLICTING_INPUTS: "the friend marked both as a point and as a line",
    ErrorCode.NOT_YOUR_MARK: "no longer sent (a code is never given another meaning)",
    ErrorCode.LANDMARK_NOT_FOUND: "no landmark of that number (to crop, or to find)",
    ErrorCode.NO_RESULT: "no answer yet, or the photo changed and it is being renewed",
    ErrorCode.DATABASE_UNAVAILABLE: "the database did not answer; try again",
    ErrorCode.INTERNAL_ERROR: "a fault of the service (logged); try again",
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
