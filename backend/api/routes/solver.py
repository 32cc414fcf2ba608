"""Stateless endpoints for scripts: solve, and draw the answer on photo 2.

They speak the solver's geometric words: photo 1 is the photo of the friend who marked the
other (``epipole1``, or ``epipolar_line1``), photo 2 the one the answer is for
(``epipole2``: where the friend of photo 1's owner is in it)."""

from __future__ import annotations

import json
from typing import Annotated, Any, Literal

from fastapi import APIRouter, File, Form, Query, UploadFile
from fastapi.responses import Response
from pydantic import BaseModel, ConfigDict, Field, JsonValue, PlainValidator, ValidationError

from backend.api.deps import SettingsDep
from backend.api.responses import PICTURE, errors, json_answer
from backend.errors import ErrorCode, RefusedError
from backend.photos.intake import store_photo
from backend.photos.pictures import decode_photo, encode_image
from backend.photos.schemas import MEDIA_TYPES, ImageFormat
from shared_solver import Camera, SolveResult, draw_overlay, solve

router = APIRouter(prefix="/api", tags=["solver"])

_EXAMPLE: dict[str, JsonValue] = {
    "points1": [[547, 598], [948, 824], [238, 1014], [327, 799], [727, 499]],
    "points2": [[693, 551], [330, 688], [1000, 1003], [1548, 1032], [564, 485]],
    "epipole1": [730, 690],
    "tap_sigma": 1.0,
    "image_size1": [1600, 1200],
    "image_size2": [1600, 1200],
}
# The same taps, three landmarks only, from two phones (one with its focal length from
# EXIF), each tap with its own precision: the camera model answers from three.
_PHONES_EXAMPLE: dict[str, JsonValue] = {
    "points1": [[547, 598], [948, 824], [238, 1014]],
    "points2": [[693, 551], [330, 688], [1000, 1003]],
    "epipole1": [730, 690],
    "points1_sigma": [1.0, 2.0, 1.0],
    "points2_sigma": [1.0, 1.0, 3.0],
    "epipole1_sigma": 1.5,
    "image_size1": [1600, 1200],
    "image_size2": [1600, 1200],
    "camera1": {"kind": "phone"},
    "camera2": {"kind": "known_focal", "focal_35mm": 30},
}

# No landmark: the friend marked, and both phones' gravity at the shutter.
_LEVEL_EXAMPLE: dict[str, JsonValue] = {
    "points1": [],
    "points2": [],
    "epipole1": [730, 690],
    "image_size1": [1600, 1200],
    "image_size2": [1600, 1200],
    "camera1": {"kind": "phone"},
    "camera2": {"kind": "phone"},
    "gravity1": [0.0, 0.999, 0.04],
    "gravity2": [0.03, 0.999, -0.02],
}
# The same with both phones' compass headings, undisturbed (5 degrees): they point to a
# stretch of the level.
_COMPASS_EXAMPLE: dict[str, JsonValue] = _LEVEL_EXAMPLE | {
    "heading1": 10.0,
    "heading2": 190.0,
    "heading_sigma_deg": 5.0,
}


def _documented_as(shape: Any) -> PlainValidator:
    """A field passed to the solver as sent, documented as ``shape``: the solver checks
    it, so a malformed one gets the solver's own code like every other field."""
    return PlainValidator(lambda value: value, json_schema_input_type=shape)


# What is known about a photo's camera: the solver's Camera, or its kind alone.
_CameraField = Annotated[Any, _documented_as(Camera | Literal["phone", "unknown"] | None)]
# One sigma (px) or one 2x2 covariance (px^2) per landmark tap.
_TapPrecisions = Annotated[Any, _documented_as(list[float] | list[list[list[float]]] | None)]
# A phone's gravity reading: three numbers.
_Direction = Annotated[Any, _documented_as(list[float] | None)]
# A sigma (px) or a 2x2 covariance (px^2) of one mark.
_MarkPrecision = Annotated[Any, _documented_as(float | list[list[float]] | None)]


class SolveRequest(BaseModel):
    """The arguments of ``shared_solver.solve``. Shapes are checked by the solver, so a
    malformed point, camera or precision gets the solver's own error code
    (``invalid_shape``, ``not_finite``, ``invalid_parameter``). The cameras are unknown
    unless said: a script may send a cropped or edited photo, which is no phone camera."""

    model_config = ConfigDict(
        json_schema_extra={"examples": [_EXAMPLE, _PHONES_EXAMPLE, _LEVEL_EXAMPLE]}
    )

    points1: Any = Field(description="Landmarks in photo 1: [[x, y], ...].")
    points2: Any = Field(description="The same landmarks, same order, in photo 2.")
    epipole1: Any = Field(None, description="[x, y] of the friend marked in photo 1.")
    epipole2: Any = Field(None, description="[x, y] of the other friend, marked in photo 2.")
    epipolar_line1: Any = Field(
        None, description="[a, b, c]: a line through the friend in photo 1."
    )
    tap_sigma: float = Field(
        2.0,
        description="Tap noise, px per axis: the precision of every tap not given its own "
        "(points1_sigma, points2_sigma, epipole1_sigma, epipole2_sigma).",
    )
    image_size1: Any = Field(None, description="[width, height] of photo 1; needed with camera1.")
    image_size2: Any = Field(None, description="[width, height] of photo 2; needed with camera2.")
    camera1: _CameraField = Field(
        None,
        description='What is known about photo 1\'s camera. {"kind": "phone"}: a phone '
        "photo, focal length unknown (a broad prior around the main camera's 26 mm); "
        '{"kind": "known_focal", "focal_35mm": 26}: its 35 mm-equivalent focal '
        "length (EXIF FocalLengthIn35mmFilm), with focal_uncertainty (relative, 0.02 by "
        'default); "phone" or "unknown" for short. Null or unknown (the default): any '
        "camera, the projective geometry (for cropped, edited or non-phone photos). With "
        "both cameras known the answer uses a pinhole model (method pinhole_*, "
        "camera_model 'pinhole', cameras) and needs fewer landmarks: 3 with the friend "
        "marked instead of 5, 1 with both friends marked instead of 3. Needs image_size1; "
        "a malformed camera is refused with invalid_parameter.",
        examples=[{"kind": "phone"}, {"kind": "known_focal", "focal_35mm": 26}],
    )
    camera2: _CameraField = Field(
        None,
        description="The same for photo 2; needs image_size2.",
        examples=[{"kind": "phone"}],
    )
    points1_sigma: _TapPrecisions = Field(
        None,
        description="The precision of each landmark tap in photo 1, same order as points1: "
        "[sigma, ...] in px, or [[[var_x, cov_xy], [cov_xy, var_y]], ...] in px^2 (symmetric, "
        "positive definite). Null: tap_sigma for each.",
        examples=[[1.0, 2.0, 1.0]],
    )
    points2_sigma: _TapPrecisions = Field(
        None,
        description="The same for points2 (photo 2).",
        examples=[[[[4.0, 1.0], [1.0, 2.0]], [[1.0, 0.0], [0.0, 1.0]], [[9.0, 0.0], [0.0, 9.0]]]],
    )
    epipole1_sigma: _MarkPrecision = Field(
        None,
        description="The precision of epipole1: a sigma in px or a 2x2 covariance in px^2; "
        "with epipolar_line1 instead, the line's sigma across it. Null: tap_sigma.",
        examples=[1.5],
    )
    epipole2_sigma: _MarkPrecision = Field(
        None,
        description="The precision of epipole2, as epipole1_sigma. Null: tap_sigma.",
        examples=[[[4.0, 0.0], [0.0, 1.0]]],
    )

    gravity1: _Direction = Field(
        None,
        description="[x, y, z]: which way is down in photo 1's camera frame at the shutter "
        "(x right along the rows, y down the columns, z out of the lens; any length): a "
        "phone held upright and level reads [0, 1, 0]. With gravity2, both cameras known "
        "and epipole1, no landmark gives the level the friend is on (method "
        "pinhole_level, curve2) and one landmark a point.",
        examples=[[0.02, 0.99, 0.1]],
    )
    gravity2: _Direction = Field(None, description="The same for photo 2.")
    gravity_sigma_deg: Any = Field(
        1.0, description="A gravity reading's standard deviation per axis, degrees."
    )
    gravity1_sigma_deg: Any = Field(
        None, description="Photo 1's reading's own sigma, degrees. Null: gravity_sigma_deg."
    )
    gravity2_sigma_deg: Any = Field(
        None, description="Photo 2's reading's own sigma, degrees. Null: gravity_sigma_deg."
    )
    heading1: Any = Field(
        None,
        description="Photo 1's compass heading at the shutter: degrees clockwise from north "
        "of the lens axis's horizontal direction (any north both phones share). With "
        "heading2 and both gravity readings, it measures the turn between the phones: no "
        "landmark gives a stretch of the level (curve2_stretch, a hint), landmarks a "
        "sharper point; where they contradict the landmarks the headings are left out "
        "(warning heading_disagrees).",
        examples=[10.0],
    )
    heading2: Any = Field(None, description="The same for photo 2.", examples=[190.0])
    heading_sigma_deg: Any = Field(
        15.0,
        description="A heading's standard deviation, degrees (steel and speakers bend compasses).",
    )
    heading1_sigma_deg: Any = Field(
        None, description="Photo 1's heading's own sigma, degrees. Null: heading_sigma_deg."
    )
    heading2_sigma_deg: Any = Field(
        None, description="Photo 2's heading's own sigma, degrees. Null: heading_sigma_deg."
    )

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
            camera1=self.camera1,
            camera2=self.camera2,
            points1_sigma=self.points1_sigma,
            points2_sigma=self.points2_sigma,
            epipole1_sigma=self.epipole1_sigma,
            epipole2_sigma=self.epipole2_sigma,
            gravity1=self.gravity1,
            gravity2=self.gravity2,
            gravity_sigma_deg=self.gravity_sigma_deg,
            gravity1_sigma_deg=self.gravity1_sigma_deg,
            gravity2_sigma_deg=self.gravity2_sigma_deg,
            heading1=self.heading1,
            heading2=self.heading2,
            heading_sigma_deg=self.heading_sigma_deg,
            heading1_sigma_deg=self.heading1_sigma_deg,
            heading2_sigma_deg=self.heading2_sigma_deg,
        )


def _answer_of(example: dict[str, JsonValue]) -> JsonValue:
    """The real solver's answer: the documented answers cannot drift from the code."""
    answer: JsonValue = SolveRequest.model_validate(example).solve().model_dump(mode="json")
    return answer


_EXAMPLES: dict[str, dict[str, JsonValue]] = {
    "projective": {
        "summary": "Five landmarks and the friend marked, cameras unknown",
        "value": _answer_of(_EXAMPLE),
    },
    "phones": {
        "summary": "Three landmarks and the friend marked, two phones, taps of their own precision",
        "value": _answer_of(_PHONES_EXAMPLE),
    },
    "level": {
        "summary": "No landmark: the friend marked and both phones' gravity give the level",
        "value": _answer_of(_LEVEL_EXAMPLE),
    },
    "compass": {
        "summary": "No landmark, gravity and compass: the level and the stretch of it they "
        "point to",
        "value": _answer_of(_COMPASS_EXAMPLE),
    },
}


@router.post(
    "/solve",
    response_model=SolveResult,
    responses={
        200: {"content": {"application/json": {"examples": _EXAMPLES}}},
        **errors(400, 413, 422),
    },
)
def solve_taps(request: SolveRequest) -> Response:
    """Where the friend is in photo 2, from the taps: exactly ``shared_solver.solve``.

    The cameras are unknown unless ``camera1`` and ``camera2`` say otherwise (the paper's
    projective geometry: 5 landmarks with the friend marked); with both (two phone photos,
    say) the answer uses a pinhole camera model and needs fewer landmarks (3 with the friend
    marked).
    """
    return json_answer(request.solve())


@router.post(
    "/overlay", responses={**PICTURE, **errors(400, 413, 415, 422)}, response_class=Response
)
def draw_on_photo(
    settings: SettingsDep,
    photo: Annotated[UploadFile, File(description="Photo 2 (JPEG, PNG, WebP, HEIC).")],
    request: Annotated[
        str,
        Form(
            description="The JSON of POST /api/solve, as a string.",
            examples=[json.dumps(_EXAMPLE), json.dumps(_PHONES_EXAMPLE)],
        ),
    ],
    format: Annotated[ImageFormat, Query(description="png or jpeg")] = "png",
) -> Response:
    """Photo 2 with the answer drawn on it (landmarks = ``points2``).

    Points are in the photo's pixels as a browser shows it (EXIF orientation applied).
    """
    try:
        parsed = SolveRequest.model_validate_json(request)
    except ValidationError as error:
        raise RefusedError(
            ErrorCode.INVALID_REQUEST, "The request field is not the JSON of /api/solve."
        ) from error
    result = parsed.solve()
    stored = store_photo(photo.file.read(), max_pixels=settings.max_photo_pixels, max_side=2**16)
    drawn = draw_overlay(decode_photo(stored.data), result, photo=2, points=parsed.points2)
    return Response(encode_image(drawn, format=format), media_type=MEDIA_TYPES[format])
