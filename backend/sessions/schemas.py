"""What the session endpoints accept and answer (pydantic; examples show in /docs)."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, Strict

Role = Literal["seeker", "buddy"]
# A JSON number, nothing that converts to one ("12", true): a tap sent as anything else is
# a bug of the client, refused rather than guessed at.
Coordinate = Annotated[float, Strict()]


class CreatedSession(BaseModel):
    session_id: str = Field(examples=["3f2a9c0e5b7d41a8b6c2d9e4f1a07b35"])
    join_code: str = Field(
        description="Eight digits (the search's number, then its secret), single use.",
        examples=["48291375"],
    )
    join_code_expires_at: datetime
    join_url: str = Field(
        description="Opening it on the buddy's phone joins directly.",
        examples=["http://192.168.1.20:8000/join/482913"],
    )
    token: str = Field(description="Send as 'Authorization: Bearer <token>'. Keep it secret.")
    role: Role = "seeker"
    expires_at: datetime


class JoinRequest(BaseModel):
    code: str = Field(
        pattern=r"^[0-9]{8}$",
        description="The seeker's eight digits: the search's number, then its secret.",
        examples=["48291375"],
    )


class Joined(BaseModel):
    session_id: str = Field(examples=["3f2a9c0e5b7d41a8b6c2d9e4f1a07b35"])
    token: str = Field(
        description="Send as 'Authorization: Bearer <token>'. Keep it secret.",
        examples=["kq3Vx0b3nUj0mB1Zy9fX2m8Lq5Wc7Rt4Hs6Dp1Ae0Io"],
    )
    role: Role = "buddy"
    expires_at: datetime


class PhotoStored(BaseModel):
    width: int = Field(
        description="Of the stored photo, px: taps are in these pixels.", examples=[2560]
    )
    height: int = Field(examples=[1920])
    scale: float = Field(
        description="Stored size / uploaded size (1.0 if not downscaled).", examples=[0.6349]
    )


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


class ParticipantState(BaseModel):
    joined: bool
    online: bool


class SessionState(BaseModel):
    """All a (re)connecting phone needs."""

    session_id: str
    you: Role
    version: int = Field(description="Bumped by every change; events say 'this changed'.")
    expires_at: datetime
    join_code: str | None = Field(None, description="Shown to the seeker until the buddy joins.")
    join_code_expires_at: datetime | None = Field(
        None, description="When that code stops working (time for a new session)."
    )
    join_url: str | None = None
    join_code_renewals: int = Field(
        0,
        description="How many times the join code was renewed because wrong codes named this "
        "search (the seeker's phone says so: a code read out before no longer works).",
    )
    participants: dict[Role, ParticipantState]
    photos: dict[Role, PhotoStored | None]
    taps: dict[Role, Taps | None]
    landmarks_needed: int = Field(
        description="How many more landmarks, common to both photos, until a position."
    )
    result: dict[str, Any] | None = Field(
        None, description="The solver's answer (as POST /api/solve returns it), when there is one."
    )
    result_version: int | None = None
    result_landmark_ids: list[int] | None = Field(
        None,
        description="Landmark ids in the order the answer uses them (residuals, suspects).",
    )
    result_error: dict[str, str] | None = Field(
        None, description="Why there is no answer although enough landmarks are tapped."
    )
