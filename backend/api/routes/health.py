"""Is the service up?"""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.responses import JSONResponse

from backend import __version__
from backend.api.deps import ServicesDep
from backend.api.errors import error_response
from backend.api.responses import errors
from backend.errors import ErrorCode

router = APIRouter(tags=["health"])


@router.get(
    "/healthz",
    responses={
        200: {"content": {"application/json": {"example": {"status": "ok"}}}},
        **errors(503),
    },
)
def health(services: ServicesDep) -> JSONResponse:
    """Ready to serve: the database answers."""
    try:
        ok = services.healthy()
    except Exception:
        ok = False
    if not ok:
        return error_response(ErrorCode.DATABASE_UNAVAILABLE, "The database does not answer.")
    return JSONResponse({"status": "ok"})


@router.get(
    "/api/version",
    responses={200: {"content": {"application/json": {"example": {"version": "0.1.0"}}}}},
)
def version() -> dict[str, str]:
    """The service's version (no database: the cheapest endpoint, also a liveness probe)."""
    return {"version": __version__}
