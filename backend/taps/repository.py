"""A participant's taps, and the answer recorded with the version it was computed for."""

from __future__ import annotations

import json
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from sqlalchemy import bindparam, select, update
from sqlalchemy.orm import Session

from backend.eventstream.log import EventType, record
from backend.participants import Participant
from backend.storage.database import Database
from backend.storage.tables import ParticipantRow, PhotoRow, SessionRow, core
from backend.storage.versions import bump_version

from .schemas import Taps, TapsChanged
from .shown import Shown

_sessions, _participants, _photos = core(SessionRow), core(ParticipantRow), core(PhotoRow)
# Core, built once: every tap runs them.
# (Bound names other than the columns': SQLAlchemy keeps those for the values.)
_SET_TAPS = (
    update(_participants)
    .where(_participants.c.session_id == bindparam("of"), _participants.c.role == bindparam("who"))
    .values(taps=bindparam("tapped"))
)
_SET_ANSWER = (
    update(_sessions)
    .where(_sessions.c.id == bindparam("of"), _sessions.c.version == bindparam("at"))
    .values(answer=bindparam("found"), answer_version=bindparam("at"))
)

# What a landmark's crop needs of the session: one participant's taps and which photo they
# are on (the photo's version names its bytes), not the whole session with its answer.
_ON_PHOTO = (
    select(_sessions.c.id, _participants.c.taps, _photos.c.version)
    .select_from(_sessions)
    .outerjoin(
        _participants,
        (_participants.c.session_id == _sessions.c.id) & (_participants.c.role == bindparam("who")),
    )
    .outerjoin(
        _photos,
        (_photos.c.session_id == _sessions.c.id) & (_photos.c.role == bindparam("who")),
    )
    .where(_sessions.c.id == bindparam("of"))
)


@dataclass(frozen=True)
class OnPhoto:
    """A participant's landmark and the photo it is on."""

    x: float
    y: float
    photo_version: int | None  # the session's version that stored the photo


class TapStore:
    def __init__(self, database: Database) -> None:
        self.database = database

    def put_taps(
        self,
        participant: Participant,
        taps: Taps,
        now: datetime,
        *,
        read: int,
        needed: int,
        answer: tuple[dict[str, Any], Shown] | None = None,
    ) -> tuple[int, bool]:
        """Replace a participant's taps (the answer goes with the old ones): the new
        version, and whether ``answer`` was recorded with them.

        ``needed`` (the landmarks still needed, before an answer) and ``answer`` (the
        answer as stored, ``StoredAnswer.as_json()``, and as the phones show it) were
        computed from the session at version ``read`` with these taps. They are recorded in
        the same transaction, so with one write, unless another change came in between: then
        they are stale, the taps' event says it cannot tell the count, and the caller answers
        the new version afresh.
        """
        sid, role = participant.session_id, participant.role
        with self.database.write() as tx:
            tx.execute(_SET_TAPS, {"of": sid, "who": role, "tapped": taps.model_dump_json()})
            version = bump_version(tx, sid)
            fresh = version == read + 1
            told = TapsChanged(
                role=role, version=version, taps=taps, landmarks_needed=needed if fresh else None
            )
            record(tx, sid, EventType.TAPS, told, now, locked=True)
            answered = fresh and answer is not None
            if answer is not None and answered:
                _record_answer(tx, sid, version, answer=answer[0], shown=answer[1], now=now)
        return version, answered

    def landmark(self, session_id: str, role: str, landmark_id: int) -> tuple[bool, OnPhoto | None]:
        """Whether the session is still there, and where ``role`` tapped landmark
        ``landmark_id`` and the photo it is on (None: no such landmark, or no photo). One
        narrow read (the taps as stored, validated when they were written), for each crop."""
        with self.database.query() as connection:
            row = connection.execute(_ON_PHOTO, {"of": session_id, "who": role}).first()
        if row is None:
            return False, None
        if row.taps is None or row.version is None:
            return True, None
        for tap in json.loads(row.taps)["landmarks"]:
            if tap["id"] == landmark_id:
                return True, OnPhoto(float(tap["x"]), float(tap["y"]), row.version)
        return True, None

    def put_answer(
        self, session_id: str, version: int, answer: dict[str, Any], shown: Shown, now: datetime
    ) -> bool:
        """Record the answer computed for ``version``, unless the session has moved on since
        (then a newer computation records its own)."""
        with self.database.write() as tx:
            return _record_answer(tx, session_id, version, answer=answer, shown=shown, now=now)


def _record_answer(
    tx: Session,
    session_id: str,
    version: int,
    *,
    answer: dict[str, Any],
    shown: Shown,
    now: datetime,
) -> bool:
    """The answer for ``version`` (``StoredAnswer.as_json()``: its caller keeps it as the
    session's, dumped once) and its event, if the session is still at that version."""
    done = tx.execute(_SET_ANSWER, {"of": session_id, "at": version, "found": json.dumps(answer)})
    if not done.rowcount:  # type: ignore[attr-defined]
        return False
    record(tx, session_id, EventType.ANSWER, shown.changed(version), now, locked=True)
    return True
