"""One JSON shape for every error: ``{"error": {"code": "...", "message": "..."}}``.

``code`` is stable and machine-readable (phones and scripts branch on it); ``message`` is a
sentence a person can act on. Services raise :class:`ApiError`; the solver's
:class:`~shared_solver.SolverError` becomes a 422 with its own code; a database that cannot
be reached (down, restarting) a 503 ``database_unavailable``, which phones retry.
"""

from __future__ import annotations

import logging

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException

from backend.storage.database import DatabaseUnavailableError
from shared_solver import SolverError

log = logging.getLogger(__name__)


class ApiError(Exception):
    """An answer other than success, with its HTTP status, stable code and sentence."""

    def __init__(
        self, status: int, code: str, message: str, headers: dict[str, str] | None = None
    ) -> None:
        super().__init__(message)
        self.status = status
        self.code = code
        self.message = message
        self.headers = headers  # e.g. Retry-After


def error_body(code: str, message: str) -> dict[str, dict[str, str]]:
    return {"error": {"code": code, "message": message}}


def error_response(
    status: int, code: str, message: str, headers: dict[str, str] | None = None
) -> JSONResponse:
    return JSONResponse(error_body(code, message), status_code=status, headers=headers)


# Codes for the statuses Starlette itself answers (unknown route, wrong method, ...).
_HTTP_CODES = {
    400: "bad_request",
    401: "unauthorized",
    403: "forbidden",
    404: "not_found",
    405: "method_not_allowed",
    413: "body_too_large",
    415: "unsupported_media_type",
    429: "too_many_attempts",
}


def install(app: FastAPI) -> None:
    """Make every error of ``app`` answer in the one shape."""

    @app.exception_handler(ApiError)
    async def api_error(_: Request, error: ApiError) -> JSONResponse:
        return error_response(error.status, error.code, error.message, error.headers)

    @app.exception_handler(SolverError)
    async def solver_error(_: Request, error: SolverError) -> JSONResponse:
        return error_response(422, error.code.value, error.message)

    @app.exception_handler(DatabaseUnavailableError)
    async def database_unavailable(_: Request, error: DatabaseUnavailableError) -> JSONResponse:
        log.warning("database unavailable: %s", error)
        return error_response(
            503, "database_unavailable", "The database does not answer just now; try again."
        )

    @app.exception_handler(RequestValidationError)
    async def invalid_request(_: Request, error: RequestValidationError) -> JSONResponse:
        return error_response(422, "invalid_request", _describe(error))

    @app.exception_handler(StarletteHTTPException)
    async def http_error(_: Request, error: StarletteHTTPException) -> JSONResponse:
        code = _HTTP_CODES.get(error.status_code, f"http_{error.status_code}")
        message = error.detail if isinstance(error.detail, str) else "Request refused."
        if error.status_code == 404 and message == "Not Found":
            message = "There is nothing at this address."
        elif error.status_code == 400 and message == "There was an error parsing the body":
            # FastAPI's words for a body that is not UTF-8 JSON or not a multipart form.
            message = "The body cannot be read: send JSON (UTF-8) or a form, as documented."
        return error_response(error.status_code, code, message)

    @app.exception_handler(Exception)
    async def unexpected(request: Request, error: Exception) -> JSONResponse:
        # The route's template, never the URL: pictures and event streams carry ?token=.
        route = getattr(request.scope.get("route"), "path", "an unknown route")
        log.exception("unexpected error in %s %s", request.method, route, exc_info=error)
        return error_response(500, "internal_error", "Something went wrong on our side; try again.")


def _describe(error: RequestValidationError) -> str:
    """The first problem of a request, as a sentence naming the field."""
    problems = error.errors()
    if not problems:
        return "The request is not valid."
    first = problems[0]
    where = ".".join(str(part) for part in first.get("loc", ()) if part not in ("body", "query"))
    what = str(first.get("msg", "is not valid")).rstrip(".")
    return f"{where}: {what}." if where else f"{what}."
