"""OpenAPI descriptions of the error shape and the picture responses, and the JSON answer,
shared by routes."""

from __future__ import annotations

from typing import Any

from fastapi.responses import Response
from pydantic import BaseModel, ConfigDict, Field


class ErrorDetail(BaseModel):
    """A refusal's code and sentence; the solver's (422) also carry its ``reason`` and the
    parameters its sentence names (the fields of ``Refusal``, those it has)."""

    model_config = ConfigDict(extra="allow")

    code: str = Field(description="Stable and machine-readable: branch on it.")
    message: str = Field(description="A sentence a person can act on.")


class Error(BaseModel):
    """The one shape of every refusal."""

    model_config = ConfigDict(extra="forbid")

    error: ErrorDetail


# Where a response is documented after FastAPI built the schema (see main.py), the shape is
# referred to by name: every route documenting errors() puts it among the components.
ERROR_SCHEMA: dict[str, Any] = {"$ref": "#/components/schemas/Error"}


def errors(*statuses: int) -> dict[int | str, dict[str, Any]]:
    """``responses=`` entries documenting the one error shape for these statuses."""
    examples = {
        400: (
            "bad_request",
            "The body cannot be read: send JSON (UTF-8) or a form, as documented.",
        ),
        401: ("unauthorized", "Send your session token: 'Authorization: Bearer <token>'."),
        403: ("forbidden", "This token opens another session."),
        404: ("session_not_found", "This session has ended."),
        409: ("photo_missing", "Upload your photo before tapping on it."),
        413: ("photo_too_large", "This photo has 60 megapixels; at most 50 are accepted."),
        415: ("unsupported_media_type", "Send a JPEG, PNG, WebP or HEIC photo."),
        422: ("too_few_landmarks", "4 landmarks marked; at least 5 are needed here."),
        429: ("too_many_attempts", "Too many wrong codes from here; wait a minute."),
        503: ("database_unavailable", "The database does not answer."),
    }
    # The solver's refusals carry their reason and parameters beside code and message.
    parameters: dict[int, dict[str, Any]] = {
        422: {"reason": "too_few_landmarks", "count": 4, "minimum": 5}
    }
    return {
        status: {
            "description": "RefusedError",
            "model": Error,
            "content": {
                "application/json": {
                    "example": {
                        "error": {
                            "code": examples[status][0],
                            **parameters.get(status, {}),
                            "message": examples[status][1],
                        }
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
            "schema": ERROR_SCHEMA,
            "example": {
                "error": {
                    "code": "invalid_request",
                    "message": "landmarks.0.x: Input should be a valid number.",
                }
            },
        }
    },
}

PICTURE: dict[int | str, dict[str, Any]] = {
    200: {
        "description": "The picture (PNG, or JPEG with ?format=jpeg).",
        "content": {"image/png": {}, "image/jpeg": {}},
    }
}


def json_answer(model: BaseModel, status_code: int = 200) -> Response:
    """``model`` as the response, serialised by the model itself. Returned as is, FastAPI
    would dump it, validate the dump against the route's ``response_model`` and serialise
    that: three passes for one. The route's ``response_model`` still documents it."""
    return Response(model.model_dump_json(), status_code=status_code, media_type="application/json")
