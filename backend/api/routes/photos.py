"""A participant's photo: upload it, and load a stored one."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, File, UploadFile
from fastapi.responses import Response

from backend.api.deps import ParticipantDep, PhotosDep, ViewerDep
from backend.api.params import RoleParam
from backend.api.responses import errors, json_answer
from backend.photos.schemas import PhotoStored

router = APIRouter(prefix="/api/sessions", tags=["sessions"])


@router.put(
    "/{session_id}/photo",
    response_model=PhotoStored,
    responses=errors(400, 401, 403, 404, 413, 415, 422, 503),
)
def put_photo(
    participant: ParticipantDep,
    photos: PhotosDep,
    photo: Annotated[UploadFile, File(description="JPEG, PNG, WebP or HEIC; any size.")],
) -> Response:
    """Upload (or replace) your photo. It is stored upright, without metadata, downscaled to
    2560 px on the long side; taps are in the stored photo's pixels. Replacing it clears
    your taps."""
    return json_answer(photos.put(participant, photo.file.read()))


@router.get(
    "/{session_id}/photo/{role}",
    responses={200: {"content": {"image/jpeg": {}}}, **errors(401, 403, 404, 503)},
    response_class=Response,
)
def stored_photo(role: RoleParam, participant: ViewerDep, photos: PhotosDep) -> Response:
    """A participant's photo as stored: upright, no metadata, taps are in its pixels."""
    data = photos.get(participant, role)
    return Response(data, media_type="image/jpeg", headers={"Cache-Control": "private"})
