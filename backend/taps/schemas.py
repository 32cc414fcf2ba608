"""What a phone sends as its taps (each PUT replaces the whole set)."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, Strict

# A JSON number, nothing that converts to one ("12", true): a tap sent as anything else is
# a bug of the client, refused rather than guessed at.
Coordinate = Annotated[float, Strict()]


class LandmarkTap(BaseModel):
    model_config = ConfigDict(allow_inf_nan=False)

    id: int = Field(
        ge=1, le=999, strict=True, description="The number people see; #3 here is #3 there."
    )
    x: Coordinate = Field(description="Stored-photo pixels, x right.")
    y: Coordinate = Field(description="Stored-photo pixels, y down.")


class Taps(BaseModel):
    """A participant's whole tap set (each PUT replaces it)."""

    model_config = ConfigDict(
        allow_inf_nan=False,
        json_schema_extra={
            "examples": [
                {
                    "landmarks": [
                        {"id": 1, "x": 412.0, "y": 230.5},
                        {"id": 2, "x": 1830.0, "y": 402.0},
                        {"id": 3, "x": 960.0, "y": 1410.0},
                    ],
                    "epipole1": [1204.0, 861.0],
                }
            ]
        },
    )

    landmarks: list[LandmarkTap] = Field(default_factory=list)
    epipole1: tuple[Coordinate, Coordinate] | None = Field(
        None, description="Seeker only: where the buddy is in the seeker's photo."
    )
    epipolar_line1: tuple[Coordinate, Coordinate, Coordinate] | None = Field(
        None,
        description="Seeker only, instead of epipole1: a line a*x + b*y + c = 0 through the buddy.",
    )
    epipole2: tuple[Coordinate, Coordinate] | None = Field(
        None, description="Buddy only, optional: where the seeker is in the buddy's photo."
    )
