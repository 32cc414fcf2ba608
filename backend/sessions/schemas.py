"""What a (re)connecting phone is told: the whole session as it sees it."""

from __future__ import annotations

from datetime import datetime
from typing import Any

from pydantic import BaseModel, Field

from backend.participants import Role
from backend.photos.schemas import PhotoStored
from backend.taps.schemas import Taps


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
