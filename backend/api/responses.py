"""OpenAPI descriptions of the error shape and the picture responses, shared by routes."""

from __future__ import annotations

from typing import Any


def errors(*statuses: int) -> dict[int | str, dict[str, Any]]:
    """``responses=`` entries documenting the one error shape for these statuses."""
    examples = {
        401: ("unauthorized", "Send your session token: 'Authorization: Bearer <token>'."),
        403: ("forbidden", "This token opens another session."),
        404: ("session_not_found", "This session has ended."),
        409: ("photo_missing", "Upload your photo before tapping on it."),
        413: ("photo_too_large", "This photo has 60 megapixels; at most 50 are accepted."),
        415: ("unsupported_media_type", "Send a JPEG, PNG, WebP or HEIC photo."),
        422: ("too_few_landmarks", "4 landmarks marked; at least 5 are needed here."),
        503: ("database_unavailable", "The database does not answer."),
    }
    return {
        status: {
            "description": "Refused",
            "content": {
                "application/json": {
                    "example": {
                        "error": {"code": examples[status][0], "message": examples[status][1]}
                    }
                }
            },
        }
        for status in statuses
    }


INVALID_REQUEST: dict[str, Any] = {
    "description": "The request does not have the documented form.",
    "content": {
        "application/json": {
            "example": {
                "error": {
                    "code": "invalid_request",
                    "message": "landmarks.0.x: Input should be a valid number.",
                }
            }
        }
    },
}

PICTURE: dict[int | str, dict[str, Any]] = {
    200: {
        "description": "The picture (PNG, or JPEG with ?format=jpeg).",
        "content": {"image/png": {}, "image/jpeg": {}},
    }
}
