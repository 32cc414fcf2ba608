"""Stateless endpoints for scripts: solve, and draw the answer on the buddy's photo."""

from __future__ import annotations

import json
from typing import Annotated, Any

from fastapi import APIRouter, File, Form, Query, UploadFile
from fastapi.responses import Response
from pydantic import BaseModel, ConfigDict, Field, JsonValue, ValidationError

from backend.api.deps import SettingsDep
from backend.api.responses import PICTURE, errors, json_answer
from backend.errors import ApiError
from backend.photos import decode_photo, encode_image, store_photo
from backend.sessions.service import MEDIA_TYPES, ImageFormat
from shared_solver import SolveResult, draw_overlay, solve

router = APIRouter(prefix="/api", tags=["solver"])

_EXAMPLE: dict[str, JsonValue] = {
    "points1": [[547, 598], [948, 824], [238, 1014], [327, 799], [727, 499]],
    "points2": [[693, 551], [330, 688], [1000, 1003], [1548, 1032], [564, 485]],
    "epipole1": [730, 690],
    "tap_sigma": 1.0,
    "image_size1": [1600, 1200],
    "image_size2": [1600, 1200],
}


class SolveRequest(BaseModel):
    """The arguments of ``shared_solver.solve``. Shapes are checked by the solver, so a
    malformed point gets the solver's own error code (``invalid_shape``, ``not_finite``)."""

    model_config = ConfigDict(json_schema_extra={"examples": [_EXAMPLE]})

    points1: Any = Field(description="Landmarks in photo 1 (the seeker's): [[x, y], ...].")
    points2: Any = Field(description="The same landmarks, same order, in photo 2.")
    epipole1: Any = Field(None, description="[x, y] of the buddy in photo 1.")
    epipole2: Any = Field(None, description="[x, y] of the seeker in photo 2.")
    epipolar_line1: Any = Field(None, description="[a, b, c]: a line through the buddy in photo 1.")
    tap_sigma: float = Field(2.0, description="Tap noise, px per axis.")
    image_size1: Any = Field(None, description="[width, height] of photo 1.")
    image_size2: Any = Field(None, description="[width, height] of photo 2.")

    def solve(self) -> SolveResult:
        return solve(
            self.points1,
            self.points2,
            epipole1=self.epipole1,
            epipole2=self.epipole2,
            epipolar_line1=self.epipolar_line1,
            tap_sigma=self.tap_sigma,
            image_size1=self.image_size1,
            image_size2=self.image_size2,
        )


# The documented answer is the real solver's, so the example cannot drift from the code.
_EXAMPLE_ANSWER = SolveRequest.model_validate(_EXAMPLE).solve().model_dump(mode="json")


@router.post(
    "/solve",
    response_model=SolveResult,
    responses={
        200: {"content": {"application/json": {"example": _EXAMPLE_ANSWER}}},
        **errors(400, 413, 422),
    },
)
def solve_taps(request: SolveRequest) -> Response:
    """Where the seeker is in photo 2, from the taps: exactly ``shared_solver.solve``."""
    return json_answer(request.solve())


@router.post(
    "/overlay", responses={**PICTURE, **errors(400, 413, 415, 422)}, response_class=Response
)
def draw_on_photo(
    settings: SettingsDep,
    photo: Annotated[UploadFile, File(description="The buddy's photo (JPEG, PNG, WebP, HEIC).")],
    request: Annotated[
        str,
        Form(
            description="The JSON of POST /api/solve, as a string.",
            examples=[json.dumps(_EXAMPLE)],
        ),
    ],
    format: Annotated[ImageFormat, Query(description="png or jpeg")] = "png",
) -> Response:
    """The buddy's photo with the answer drawn on it (landmarks = ``points2``).

    Points are in the photo's pixels as a browser shows it (EXIF orientation applied).
    """
    try:
        parsed = SolveRequest.model_validate_json(request)
    except ValidationError as error:
        raise ApiError(
            422, "invalid_request", "The request field is not the JSON of /api/solve."
        ) from error
    result = parsed.solve()
    stored = store_photo(photo.file.read(), max_pixels=settings.max_photo_pixels, max_side=2**16)
    drawn = draw_overlay(decode_photo(stored.data), result, view="buddy", points=parsed.points2)
    return Response(encode_image(drawn, format=format), media_type=MEDIA_TYPES[format])
