"""What a (re)connecting phone is told: the whole session as it sees it."""

from __future__ import annotations

from datetime import datetime

from pydantic import BaseModel, Field

from backend.eventstream.schemas import PresenceChanged, SessionEnded
from backend.pairing.schemas import CodeRenewed
from backend.participants import Role
from backend.photos.schemas import PhotoChanged, PhotoStored
from backend.taps.schemas import Answer, AnswerChanged, Taps, TapsChanged
from shared_solver import Refusal


class ParticipantState(BaseModel):
    joined: bool
    online: bool


class SessionState(BaseModel):
    """All a (re)connecting phone needs. Maps are keyed by who: the friend who started the
    search and the one who joined it; ``you`` says which one is asking."""

    session_id: str
    you: Role
    version: int = Field(
        description="Bumped by every change; each change's event names the version it made."
    )
    expires_at: datetime
    join_code: str | None = Field(
        None, description="Shown to the starter until their friend joins."
    )
    join_code_expires_at: datetime | None = Field(
        None, description="When that code stops working (time for a new session)."
    )
    join_url: str | None = None
    join_code_renewals: int = Field(
        0,
        description="How many times the join code was renewed because wrong codes named this "
        "search (the starter's phone says so: a code read out before no longer works).",
    )
    participants: dict[Role, ParticipantState]
    photos: dict[Role, PhotoStored | None]
    taps: dict[Role, Taps | None]
    landmarks_needed: int = Field(
        description="How many more landmarks, tapped in both photos, until a position."
    )
    answer: Answer | None = Field(
        None,
        description="Where each friend is in the other's photo, from both phones' taps; "
        "answer.in_photo[you] is yours.",
    )
    answer_version: int | None = Field(None, description="The version the answer is for.")
    answer_error: Refusal | None = Field(
        None,
        description="Why there is no answer although enough landmarks are tapped: the "
        "solver's code, its reason and parameters (photo 1 or 2 as in answer's photo order: "
        "message says them as your photo and your friend's photo) and message.",
    )


class SessionEvents(BaseModel):
    """The data of each event of a session's stream (``GET /api/sessions/{id}/events``), by
    event type: JSON on the event's ``data:`` line.

    A change's event carries what the other phone needs to show it: a phone whose state is
    at the version before applies it, and reads nothing more; one that finds a version
    missing (it was away, or the event cannot tell: ``landmarks_needed`` null, ``code``)
    fetches the state. An ``answer`` event is for the version it names."""

    joined: PresenceChanged
    code: CodeRenewed
    photo: PhotoChanged
    taps: TapsChanged
    answer: AnswerChanged
    left: PresenceChanged
    expired: SessionEnded
