"""Typed dependencies, defined once: every route reuses them.

The ones that only read the request are ``async``: FastAPI runs a plain ``def`` dependency in
a worker thread, a hop that costs more than the work. The ones that query the database stay
plain functions, off the event loop.
"""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Query, Request
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

from backend.sessions.service import SessionService
from backend.settings import Settings
from backend.storage.repository import Participant

_bearer = HTTPBearer(
    auto_error=False, description="The token from creating or joining the session."
)


async def get_service(request: Request) -> SessionService:
    service: SessionService = request.app.state.service
    return service


async def get_settings(request: Request) -> Settings:
    settings: Settings = request.app.state.settings
    return settings


async def base_url(request: Request) -> str:
    """This app's URL as the caller reached it (for join links)."""
    return str(request.base_url)


async def client_address(request: Request) -> str:
    """The caller's address: the direct peer, or, through a trusted proxy, the address
    the proxy says it serves (uvicorn's ``--proxy-headers`` rewrites ``request.client``)."""
    return request.client.host if request.client else ""


ServiceDep = Annotated[SessionService, Depends(get_service)]
SettingsDep = Annotated[Settings, Depends(get_settings)]
BaseUrlDep = Annotated[str, Depends(base_url)]
ClientAddressDep = Annotated[str, Depends(client_address)]
Credentials = Annotated[HTTPAuthorizationCredentials | None, Depends(_bearer)]


def participant(session_id: str, service: ServiceDep, credentials: Credentials) -> Participant:
    """The caller, from its bearer token, which must open this session."""
    return service.authenticate(credentials.credentials if credentials else None, session_id)


def viewer(
    session_id: str,
    service: ServiceDep,
    credentials: Credentials,
    token: Annotated[
        str | None,
        Query(description="The token, for EventSource and <img>, which cannot send headers."),
    ] = None,
) -> Participant:
    """Like :func:`participant`, also accepting ``?token=`` (pictures and event streams)."""
    return service.authenticate(credentials.credentials if credentials else token, session_id)


ParticipantDep = Annotated[Participant, Depends(participant)]
ViewerDep = Annotated[Participant, Depends(viewer)]
