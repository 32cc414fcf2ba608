"""Typed dependencies, defined once: every route reuses them.

The ones that only read the request are ``async``: FastAPI runs a plain ``def`` dependency in
a worker thread, a hop that costs more than the work. The ones that query the database stay
plain functions, off the event loop.
"""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Query, Request
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

from backend.eventstream.stream import EventStreams
from backend.pairing.service import PairingService
from backend.participants import Participant
from backend.photos.service import PhotoService
from backend.sessions.state import StateService
from backend.settings import Settings
from backend.taps.pictures import PictureService
from backend.wiring import Services

_bearer = HTTPBearer(
    auto_error=False, description="The token from creating or joining the session."
)


async def get_services(request: Request) -> Services:
    services: Services = request.app.state.services
    return services


async def get_pairing(request: Request) -> PairingService:
    return (await get_services(request)).pairing


async def get_photos(request: Request) -> PhotoService:
    return (await get_services(request)).photos


async def get_pictures(request: Request) -> PictureService:
    return (await get_services(request)).pictures


async def get_state(request: Request) -> StateService:
    return (await get_services(request)).state


async def get_streams(request: Request) -> EventStreams:
    return (await get_services(request)).streams


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


ServicesDep = Annotated[Services, Depends(get_services)]
PairingDep = Annotated[PairingService, Depends(get_pairing)]
PhotosDep = Annotated[PhotoService, Depends(get_photos)]
PicturesDep = Annotated[PictureService, Depends(get_pictures)]
StateDep = Annotated[StateService, Depends(get_state)]
StreamsDep = Annotated[EventStreams, Depends(get_streams)]
SettingsDep = Annotated[Settings, Depends(get_settings)]
BaseUrlDep = Annotated[str, Depends(base_url)]
ClientAddressDep = Annotated[str, Depends(client_address)]
Credentials = Annotated[HTTPAuthorizationCredentials | None, Depends(_bearer)]


def participant(session_id: str, pairing: PairingDep, credentials: Credentials) -> Participant:
    """The caller, from its bearer token, which must open this session."""
    return pairing.authenticate(credentials.credentials if credentials else None, session_id)


def viewer(
    session_id: str,
    pairing: PairingDep,
    credentials: Credentials,
    token: Annotated[
        str | None,
        Query(description="The token, for EventSource and <img>, which cannot send headers."),
    ] = None,
) -> Participant:
    """Like :func:`participant`, also accepting ``?token=`` (pictures and event streams)."""
    return pairing.authenticate(credentials.credentials if credentials else token, session_id)


ParticipantDep = Annotated[Participant, Depends(participant)]
ViewerDep = Annotated[Participant, Depends(viewer)]
