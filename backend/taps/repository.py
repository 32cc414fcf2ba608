"""A participant's taps, and the answer recorded with the version it was computed for."""

from __future__ import annotations

import json
from datetime import datetime
from typing import Any

from sqlalchemy import update
from sqlalchemy.orm import Session

from backend.eventstream.log import EventType, record
from backend.participants import Participant
from backend.storage.database import Database
from backend.storage.tables import ParticipantRow, SessionRow
from backend.storage.versions import bump_version


class TapStore:
    def __init__(self, database: Database) -> None:
        self.database = database

    def put_taps(
        self,
        participant: Participant,
        taps: dict[str, Any],
        now: datetime,
        answer: tuple[int, dict[str, Any]] | None = None,
    ) -> tuple[int, bool]:
        """Replace a participant's taps (the answer goes with the old ones): the new
        version, and whether ``answer`` was recorded with them.

        ``answer``: (the version it was computed after, the answer), computed from the
        session at that version with these taps. It is recorded in the same transaction,
        so with one write, unless another change came in between (then it is stale, and the
        caller answers the new version afresh).
        """
        sid, role = participant.session_id, participant.role
        with self.database.write() as tx:
            tx.execute(
                update(ParticipantRow)
                .where(ParticipantRow.session_id == sid, ParticipantRow.role == role)
                .values(taps=json.dumps(taps))
            )
            version = bump_version(tx, sid)
            record(tx, sid, EventType.TAPS, {"role": role, "version": version}, now)
            answered = answer is not None and answer[0] + 1 == version
            if answer is not None and answered:
                _record_answer(tx, sid, version, answer[1], now)
        return version, answered

    def put_answer(
        self, session_id: str, version: int, answer: dict[str, Any] | None, now: datetime
    ) -> bool:
        """Record the answer computed for ``version``, unless the session has moved on since
        (then a newer computation records its own)."""
        with self.database.write() as tx:
            return _record_answer(tx, session_id, version, answer, now)


def _record_answer(
    tx: Session, session_id: str, version: int, answer: dict[str, Any] | None, now: datetime
) -> bool:
    """The answer for ``version`` and its event, if the session is still at that version."""
    done = tx.execute(
        update(SessionRow)
        .where(SessionRow.id == session_id, SessionRow.version == version)
        .values(answer=None if answer is None else json.dumps(answer), answer_version=version)
    )
    if not done.rowcount:  # type: ignore[attr-defined]
        return False
    record(tx, session_id, EventType.ANSWER, {"version": version}, now)
    return True
