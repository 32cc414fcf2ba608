"""A session's version: bumped by every change a phone should see, in the change's own
transaction; the answer records the version it was computed for."""

from __future__ import annotations

from sqlalchemy import update
from sqlalchemy.orm import Session

from .tables import SessionRow


def bump_version(tx: Session, session_id: str) -> int:
    """A new version; the answer was for the old one, so it goes."""
    version = tx.scalar(
        update(SessionRow)
        .where(SessionRow.id == session_id)
        .values(version=SessionRow.version + 1, answer=None, answer_version=None)
        .returning(SessionRow.version)
    )
    assert version is not None  # the caller holds a valid token of this session
    return int(version)
