"""Taps, and the pictures drawn from them: the answer on a photo, a landmark's crop."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, File, Form, Path, Query, UploadFile
from fastapi.responses import Response

from backend.api.deps import BaseUrlDep, ParticipantDep, PicturesDep, StateDep, ViewerDep
from backend.api.params import FormatParam, RoleParam
from backend.api.responses import PICTURE, errors, json_answer
from backend.limits import MAX_LANDMARK_ID
from backend.photos.schemas import MEDIA_TYPES
from backend.sessions.schemas import SessionState
from backend.taps.schemas import LandmarkSuggestion, Reanchored, Taps

router = APIRouter(prefix="/api/sessions", tags=["sessions"])


@router.put(
    "/{session_id}/taps",
    response_model=SessionState,
    responses=errors(400, 401, 403, 404, 409, 413, 422, 503),
)
def put_taps(
    taps: Taps, participant: ParticipantDep, state: StateDep, base: BaseUrlDep
) -> Response:
    """Replace your landmarks and, if you can see your friend, your friend mark (or a line
    through them). The answer is recomputed and returned in the state."""
    return json_answer(state.put_taps(participant, taps, base))


@router.get(
    "/{session_id}/overlay/{role}",
    responses={**PICTURE, **errors(401, 403, 404, 409, 503)},
    response_class=Response,
)
def overlay(
    role: RoleParam,
    participant: ViewerDep,
    pictures: PicturesDep,
    format: FormatParam = "jpeg",
    layer: Annotated[
        bool,
        Query(
            description="true: the drawing alone, a PNG transparent elsewhere (format aside): "
            "tens of kB, for a phone that shows its own photo under it"
        ),
    ] = False,
) -> Response:
    """That participant's photo with the answer drawn for their phone."""
    data = pictures.overlay(participant, role, format, layer)
    media_type = MEDIA_TYPES["png" if layer else format]
    return Response(data, media_type=media_type, headers={"Cache-Control": "private"})


@router.post(
    "/{session_id}/reanchor",
    response_model=Reanchored,
    responses=errors(400, 401, 403, 404, 409, 413, 422, 503),
)
def reanchor(
    participant: ParticipantDep,
    pictures: PicturesDep,
    frame: Annotated[
        UploadFile, File(description="A frame of your live view, JPEG; 960 px long is plenty.")
    ],
    frame_focal_px: Annotated[
        float | None,
        Form(
            gt=0,
            le=100_000,
            description="The frame's focal length, px, when known.",
            examples=[740.0],
        ),
    ] = None,
) -> Reanchored:
    """How your phone has turned since your photo: a frame of its live view, taken where you
    stood, matched to your photo ("Show me" resets its drift with it). The frame is not
    kept. 422 ``no_solution`` (reason ``frame_not_matched``) when it does not match."""
    return pictures.reanchor(participant, frame.file.read(), frame_focal_px)


@router.get(
    "/{session_id}/landmarks/{role}/{landmark_id}/crop",
    responses={200: {"content": {"image/jpeg": {}}}, **errors(401, 403, 404, 503)},
    response_class=Response,
)
def landmark_crop(
    role: RoleParam,
    landmark_id: Annotated[int, Path(ge=1, le=MAX_LANDMARK_ID)],
    participant: ViewerDep,
    pictures: PicturesDep,
) -> Response:
    """A small JPEG around one landmark of that participant's photo: "find #3"."""
    data = pictures.crop(participant, role, landmark_id)
    return Response(data, media_type="image/jpeg", headers={"Cache-Control": "private"})


@router.get(
    "/{session_id}/landmarks/{role}/{landmark_id}/suggestion",
    response_model=LandmarkSuggestion,
    responses=errors(401, 403, 404, 409, 503),
)
def landmark_suggestion(
    role: RoleParam,
    landmark_id: Annotated[int, Path(ge=1, le=MAX_LANDMARK_ID)],
    participant: ViewerDep,
    pictures: PicturesDep,
) -> LandmarkSuggestion:
    """Where landmark #n, tapped by the other phone, probably is in that participant's
    photo: a sure match of the other photo's patch along its band, or none."""
    return pictures.suggestion(participant, role, landmark_id)
