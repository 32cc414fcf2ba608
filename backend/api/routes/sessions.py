"""The two-phone flow: create, join, photo, taps, state, overlays, crops, delete."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, File, Path, Query, UploadFile
from fastapi.responses import Response

from backend.api.deps import (
    BaseUrlDep,
    ClientAddressDep,
    ParticipantDep,
    ServiceDep,
    ViewerDep,
)
from backend.api.responses import PICTURE, errors, json_answer
from backend.sessions.schemas import (
    CreatedSession,
    Joined,
    JoinRequest,
    PhotoStored,
    Role,
    SessionState,
    Taps,
)
from backend.sessions.service import MEDIA_TYPES, ImageFormat

router = APIRouter(prefix="/api/sessions", tags=["sessions"])

RoleParam = Annotated[Role, Path(description="Whose photo: seeker (photo 1) or buddy (photo 2).")]
FormatParam = Annotated[ImageFormat, Query(description="jpeg (photos: small, fast) or png")]


@router.post("", status_code=201, response_model=CreatedSession, responses=errors(503))
def create_session(service: ServiceDep, base: BaseUrlDep) -> Response:
    """The seeker starts a search: a session, a join code for the buddy, the seeker's token."""
    return json_answer(service.create(base), status_code=201)


@router.post("/join", response_model=Joined, responses=errors(400, 404, 413, 422, 429, 503))
def join_session(request: JoinRequest, service: ServiceDep, client: ClientAddressDep) -> Response:
    """The buddy joins with the eight-digit code (single use, valid 10 minutes). Wrong codes
    are limited per client address and overall (429 ``too_many_attempts`` with
    ``Retry-After``, seconds), and a code that wrong codes named five times is renewed."""
    return json_answer(service.join(request.code, client))


@router.get("/{session_id}", response_model=SessionState, responses=errors(401, 403, 404, 503))
def session_state(participant: ParticipantDep, service: ServiceDep, base: BaseUrlDep) -> Response:
    """Everything a (re)connecting phone needs: who is online, photos, taps, the answer."""
    return json_answer(service.state(participant, base))


@router.put(
    "/{session_id}/photo",
    response_model=PhotoStored,
    responses=errors(400, 401, 403, 404, 413, 415, 422, 503),
)
def put_photo(
    participant: ParticipantDep,
    service: ServiceDep,
    photo: Annotated[UploadFile, File(description="JPEG, PNG, WebP or HEIC; any size.")],
) -> Response:
    """Upload (or replace) your photo. It is stored upright, without metadata, downscaled to
    2560 px on the long side; taps are in the stored photo's pixels. Replacing it clears
    your taps."""
    return json_answer(service.put_photo(participant, photo.file.read()))


@router.put(
    "/{session_id}/taps",
    response_model=SessionState,
    responses=errors(400, 401, 403, 404, 409, 413, 422, 503),
)
def put_taps(
    taps: Taps, participant: ParticipantDep, service: ServiceDep, base: BaseUrlDep
) -> Response:
    """Replace your landmarks (and, for the seeker, the buddy mark or line; for the buddy,
    optionally the seeker mark). The answer is recomputed and returned in the state."""
    return json_answer(service.put_taps(participant, taps, base))


@router.get(
    "/{session_id}/photo/{role}",
    responses={200: {"content": {"image/jpeg": {}}}, **errors(401, 403, 404, 503)},
    response_class=Response,
)
def stored_photo(role: RoleParam, participant: ViewerDep, service: ServiceDep) -> Response:
    """A participant's photo as stored: upright, no metadata, taps are in its pixels."""
    data = service.photo(participant, role)
    return Response(data, media_type="image/jpeg", headers={"Cache-Control": "private"})


@router.get(
    "/{session_id}/overlay/{role}",
    responses={**PICTURE, **errors(401, 403, 404, 409, 503)},
    response_class=Response,
)
def overlay(
    role: RoleParam,
    participant: ViewerDep,
    service: ServiceDep,
    format: FormatParam = "jpeg",
) -> Response:
    """That participant's photo with the answer drawn for their phone."""
    data = service.overlay(participant, role, format)
    return Response(data, media_type=MEDIA_TYPES[format], headers={"Cache-Control": "private"})


@router.get(
    "/{session_id}/landmarks/{role}/{landmark_id}/crop",
    responses={200: {"content": {"image/jpeg": {}}}, **errors(401, 403, 404, 503)},
    response_class=Response,
)
def landmark_crop(
    role: RoleParam,
    landmark_id: Annotated[int, Path(ge=1, le=999)],
    participant: ViewerDep,
    service: ServiceDep,
) -> Response:
    """A small JPEG around one landmark of that participant's photo: "find #3"."""
    data = service.crop(participant, role, landmark_id)
    return Response(data, media_type="image/jpeg", headers={"Cache-Control": "private"})


@router.delete("/{session_id}", status_code=204, responses=errors(401, 403, 503))
def delete_session(participant: ParticipantDep, service: ServiceDep) -> Response:
    """Delete now: photos, taps and answer are gone at once, for both phones."""
    service.delete(participant)
    return Response(status_code=204)
