"""Which phones are online: a phone is online while its event stream is open (the stream
marks it seen when it opens, the keeper every ``online_seconds / 3`` while it stays open,
and unseen when it closes)."""

from __future__ import annotations

from collections.abc import Sequence
from datetime import datetime

from sqlalchemy import bindparam, select, tuple_, update

from backend.participants import Participant
from backend.storage.database import Database
from backend.storage.tables import ParticipantRow, SessionRow, core

_SEEN_BATCH = 500  # participants per statement (SQLite binds at most 32766 values)
_sessions, _participants = core(SessionRow), core(ParticipantRow)
# Built once: every stream runs them.
_EXPIRES = select(_sessions.c.expires_at).where(_sessions.c.id == bindparam("session_id"))
_SEEN = (
    update(_participants)
    .where(_participants.c.session_id == bindparam("of"), _participants.c.role == bindparam("who"))
    .values(last_seen_at=bindparam("at"))
)


class Presence:
    def __init__(self, database: Database) -> None:
        self.database = database

    def seen(self, participant: Participant, when: datetime | None) -> None:
        """Mark a participant's event stream alive at ``when`` (None: gone offline)."""
        with self.database.write() as tx:
            tx.execute(_SEEN, {"of": participant.session_id, "who": participant.role, "at": when})

    def seen_all(self, participants: Sequence[Participant], when: datetime) -> None:
        """Mark all these participants' event streams alive at ``when``, in one write."""
        keys = [(p.session_id, p.role) for p in participants]
        with self.database.write() as tx:
            for start in range(0, len(keys), _SEEN_BATCH):
                tx.execute(
                    update(ParticipantRow)
                    .where(
                        tuple_(ParticipantRow.session_id, ParticipantRow.role).in_(
                            keys[start : start + _SEEN_BATCH]
                        )
                    )
                    .values(last_seen_at=when)
                )

    def expires_at(self, session_id: str) -> datetime | None:
        """When the session ends; None when it is gone already."""
        with self.database.query() as connection:
            value = connection.scalar(_EXPIRES, {"session_id": session_id})
        return None if value is None else value
