"""A participant's photo: upload it, and load a stored one."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, File, Form, UploadFile
from fastapi.responses import Response

from backend.api.deps import ParticipantDep, PhotosDep, ViewerDep
from backend.api.params import RoleParam
from backend.api.responses import errors, json_answer
from backend.photos.gravity import gravity as read_gravity
from backend.photos.heading import heading as read_heading
from backend.photos.lens import LensFacts
from backend.photos.schemas import PhotoStored

router = APIRouter(prefix="/api/sessions", tags=["sessions"])

# What the phone read of the photo's EXIF before shrinking it (the shrunk copy keeps none).
_Millimetres = Annotated[float | None, Form(gt=0, le=10_000, examples=[26.0])]
_Words = Annotated[str | None, Form(max_length=64, examples=["Google"])]


@router.put(
    "/{session_id}/photo",
    response_model=PhotoStored,
    responses=errors(400, 401, 403, 404, 413, 415, 422, 503),
)
def put_photo(
    participant: ParticipantDep,
    photos: PhotosDep,
    photo: Annotated[UploadFile, File(description="JPEG, PNG, WebP or HEIC; any size.")],
    *,
    focal_35mm: _Millimetres = None,
    focal_mm: _Millimetres = None,
    make: _Words = None,
    model: _Words = None,
    digital_zoom: Annotated[float | None, Form(ge=0, le=1000, examples=[1.0])] = None,
    gravity: Annotated[
        list[float] | None,
        Form(
            min_length=3,
            max_length=3,
            description="Which way was down at the shutter (the app's own camera): x, y, z "
            "in the stored photo's camera frame (x right along its rows, y down its "
            "columns, z out of the lens), the field sent three times; any length.",
            examples=[[0.02, 0.999, 0.04]],
        ),
    ] = None,
    gravity_sigma_deg: Annotated[
        float | None,
        Form(
            description="The reading's standard deviation per axis, degrees (default 1).",
            examples=[1.0],
        ),
    ] = None,
    heading: Annotated[
        float | None,
        Form(
            description="Which way the lens looked at the shutter (the app's own camera): "
            "degrees clockwise from north (magnetic will do: both phones' north is the "
            "same), seen from above; any finite number, kept wrapped to [0, 360). Used only "
            "with both photos' gravity and heading.",
            examples=[131.5],
        ),
    ] = None,
    heading_sigma_deg: Annotated[
        float | None,
        Form(
            description="The heading's standard deviation, degrees (default 15).",
            examples=[15.0],
        ),
    ] = None,
) -> Response:
    """Upload (or replace) your photo. It is stored upright, without metadata, downscaled to
    2560 px on the long side; taps are in the stored photo's pixels. Replacing it clears
    your taps.

    The lens: read from the photo's EXIF when it has it; else from the EXIF fields the phone
    read before shrinking it (``focal_35mm``: FocalLengthIn35mmFilm, ``focal_mm``:
    FocalLength, ``make``, ``model``, ``digital_zoom``: DigitalZoomRatio). Only the focal
    length is kept. ``gravity``: which way was down at the shutter, as the phone read it;
    with both photos' the friend's level needs no landmark and a point one. ``heading``:
    which way the lens looked, from the phone's compass; with both photos' gravity and
    heading, the stretch of the level the compasses point to (a hint)."""
    told = LensFacts(focal_35mm, focal_mm, make, model, digital_zoom)
    reading = read_gravity(gravity, gravity_sigma_deg)
    compass = read_heading(heading, heading_sigma_deg)
    return json_answer(photos.put(participant, photo.file.read(), told, reading, compass))


@router.get(
    "/{session_id}/photo/{role}",
    responses={200: {"content": {"image/jpeg": {}}}, **errors(401, 403, 404, 503)},
    response_class=Response,
)
def stored_photo(role: RoleParam, participant: ViewerDep, photos: PhotosDep) -> Response:
    """A participant's photo as stored: upright, no metadata, taps are in its pixels."""
    data = photos.get(participant, role)
    return Response(data, media_type="image/jpeg", headers={"Cache-Control": "private"})
