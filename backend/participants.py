"""Who is asking: one of the two phones of a session, as its bearer token says."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

Role = Literal["seeker", "buddy"]
ROLES: tuple[Role, Role] = ("seeker", "buddy")


@dataclass(frozen=True)
class Participant:
    session_id: str
    role: Role
