"""One JSON shape for every error: ``{"error": {"code": "...", "message": "..."}}``.

``code`` is stable and machine-readable (phones and scripts branch on it); ``message`` is a
sentence a person can act on. The domain's :class:`~backend.errors.RefusedError` is answered
with its code's one status; the solver's :class:`~shared_solver.SolverError` becomes a 422
with its own code, and its refusal's reason and parameters beside them; a database that
cannot be reached (down, restarting) a 503 ``database_unavailable``, which phones retry.
"""

from __future__ import annotations

import logging

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException

from backend.errors import STATUS, ErrorCode, RefusedError
from backend.storage.database import DatabaseUnavailableError
from shared_solver import SolverError

log = logging.getLogger(__name__)

# Codes for the statuses Starlette itself answers (unknown route, wrong method, body limit).
_HTTP_CODES = {
    400: ErrorCode.BAD_REQUEST,
    401: ErrorCode.UNAUTHORIZED,
    403: ErrorCode.FORBIDDEN,
    404: ErrorCode.NOT_FOUND,
    405: ErrorCode.METHOD_NOT_ALLOWED,
    413: ErrorCode.BODY_TOO_LARGE,
    415: ErrorCode.UNSUPPORTED_MEDIA_TYPE,
}

# Starlette's and FastAPI's own words for those statuses, as sentences a person can act on.
_HTTP_WORDS = {
    (404, "Not Found"): "There is nothing at this address.",
    # Its Allow header says which methods it takes.
    (405, "Method Not Allowed"): "This address does not take that method: see the Allow header.",
    # FastAPI's words for a body that is not UTF-8 JSON or not a multipart form.
    (400, "There was an error parsing the body"): (
        "The body cannot be read: send JSON (UTF-8) or a form, as documented."
    ),
}


def error_body(code: str, message: str) -> dict[str, dict[str, str]]:
    return {"error": {"code": code, "message": message}}


def error_response(
    code: ErrorCode, message: str, headers: dict[str, str] | None = None
) -> JSONResponse:
    return JSONResponse(error_body(code, message), status_code=STATUS[code], headers=headers)


def install(app: FastAPI, max_body_bytes: int) -> None:
    """Make every error of ``app`` answer in the one shape."""

    @app.exception_handler(RefusedError)
    async def refused(_: Request, error: RefusedError) -> JSONResponse:
        headers = None if error.retry_after is None else {"Retry-After": str(error.retry_after)}
        return error_response(error.code, error.message, headers)

    @app.exception_handler(SolverError)
    async def solver_error(_: Request, error: SolverError) -> JSONResponse:
        # Its code and message, with the reason and parameters they were worded from.
        body = {"error": error.refusal.model_dump(mode="json", exclude_none=True)}
        return JSONResponse(body, status_code=422)

    @app.exception_handler(DatabaseUnavailableError)
    async def database_unavailable(_: Request, error: DatabaseUnavailableError) -> JSONResponse:
        log.warning("database unavailable: %s", error)
        return error_response(
            ErrorCode.DATABASE_UNAVAILABLE, "The database does not answer just now; try again."
        )

    @app.exception_handler(RequestValidationError)
    async def invalid_request(_: Request, error: RequestValidationError) -> JSONResponse:
        return error_response(ErrorCode.INVALID_REQUEST, _describe(error))

    @app.exception_handler(StarletteHTTPException)
    async def http_error(_: Request, error: StarletteHTTPException) -> JSONResponse:
        code = _HTTP_CODES.get(error.status_code)
        message = error.detail if isinstance(error.detail, str) else "Request refused."
        message = _HTTP_WORDS.get((error.status_code, message), message)
        if error.status_code == 413:
            message = f"The request is larger than {max_body_bytes // 1_000_000} MB."
        body = error_body(code or f"http_{error.status_code}", message)
        return JSONResponse(body, status_code=error.status_code, headers=error.headers)

    @app.exception_handler(Exception)
    async def unexpected(request: Request, error: Exception) -> JSONResponse:
        # The route's template, never the URL: pictures and event streams carry ?token=.
        route = getattr(request.scope.get("route"), "path", "an unknown route")
        log.exception("unexpected error in %s %s", request.method, route, exc_info=error)
        return error_response(
            ErrorCode.INTERNAL_ERROR, "Something went wrong on our side; try again."
        )


def _describe(error: RequestValidationError) -> str:
    """The first problem of a request, as a sentence naming the field."""
    problems = error.errors()
    if not problems:
        return "The request is not valid."
    first = problems[0]
    where = ".".join(str(part) for part in first.get("loc", ()) if part not in ("body", "query"))
    what = str(first.get("msg", "is not valid")).rstrip(".")
    return f"{where}: {what}." if where else f"{what}."
