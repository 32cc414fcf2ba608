"""A session's version: bumped by every change a phone should see, in the change's own
transaction; the answer records the version it was computed for."""

from __future__ import annotations

from sqlalchemy import bindparam, update
from sqlalchemy.orm import Session

from backend.errors import ErrorCode, RefusedError

from .tables import SessionRow, core

_sessions = core(SessionRow)
# Core, built once: every change runs it.
_BUMP = (
    update(_sessions)
    .where(_sessions.c.id == bindparam("of"))
    .values(version=_sessions.c.version + 1, answer=None, answer_version=None)
    .returning(_sessions.c.version)
)


def bump_version(tx: Session, session_id: str) -> int:
    """A new version; the answer was for the old one, so it goes."""
    version = tx.scalar(_BUMP, {"of": session_id})
    if version is None:  # deleted since the caller's token was checked (Delete now, say)
        raise RefusedError(ErrorCode.SESSION_NOT_FOUND, "This session has ended.")
    return int(version)
