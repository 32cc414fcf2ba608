"""What the stream's own events carry: a phone came or went, the session ended. The events
of a change carry what the other phone needs to show it (each domain's ``...Changed``;
``backend.sessions.schemas.SessionEvents`` lists them all)."""

from __future__ import annotations

from pydantic import BaseModel, Field

from backend.participants import Role


class PresenceChanged(BaseModel):
    """Events ``joined`` and ``left``: a phone's event stream opened or closed; ``joined``
    also when the joiner joins the search."""

    role: Role
    online: bool = Field(description="Whether that phone's event stream is open now.")
    version: int | None = Field(
        None,
        description="Set when the joiner joined the search: the version that made (the "
        "starter's join code is gone). Unset: presence only, no change of the session.",
    )


class SessionEnded(BaseModel):
    """Event ``expired``: the session ended (deleted, or its time is up); sent, not stored."""

    reason: str = Field(examples=["The session ended."])
