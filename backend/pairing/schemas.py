"""What starting, joining and ending a search accept and answer."""

from __future__ import annotations

from datetime import datetime

from pydantic import BaseModel, Field

from backend.limits import JOIN_CODE_LENGTH
from backend.participants import Role


class CreatedSession(BaseModel):
    session_id: str = Field(examples=["3f2a9c0e5b7d41a8b6c2d9e4f1a07b35"])
    join_code: str = Field(
        description="Eight digits (the search's number, then its secret), single use.",
        examples=["48291375"],
    )
    join_code_expires_at: datetime
    join_url: str = Field(
        description="Opening it on the friend's phone joins directly.",
        examples=["http://192.168.1.20:8000/join/48291375"],
    )
    token: str = Field(description="Send as 'Authorization: Bearer <token>'. Keep it secret.")
    role: Role = "starter"
    expires_at: datetime


class JoinRequest(BaseModel):
    code: str = Field(
        pattern=rf"^[0-9]{{{JOIN_CODE_LENGTH}}}$",
        description="The starter's eight digits: the search's number, then its secret.",
        examples=["48291375"],
    )


class Joined(BaseModel):
    session_id: str = Field(examples=["3f2a9c0e5b7d41a8b6c2d9e4f1a07b35"])
    token: str = Field(
        description="Send as 'Authorization: Bearer <token>'. Keep it secret.",
        examples=["kq3Vx0b3nUj0mB1Zy9fX2m8Lq5Wc7Rt4Hs6Dp1Ae0Io"],
    )
    role: Role = "joiner"
    expires_at: datetime


class CodeRenewed(BaseModel):
    """Event ``code``: the join code was renewed after wrong guesses named its search (the
    starter's phone fetches the state for the new one: codes go in no event)."""

    renewed: bool = True
    version: int = Field(description="The session's version the renewal made.")
