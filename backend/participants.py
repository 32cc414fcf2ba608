"""Who is asking: one of the two friends of a search, as its bearer token says.

The two are alike in everything but how they came: one started the search, the other
joined it with the code. Either may see the other and mark them; each phone is told where
its friend is in its own photo.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

Role = Literal["starter", "joiner"]
ROLES: tuple[Role, Role] = ("starter", "joiner")


def other(role: Role) -> Role:
    return "joiner" if role == "starter" else "starter"


@dataclass(frozen=True)
class Participant:
    session_id: str
    role: Role
