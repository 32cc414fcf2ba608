"""Sessions and their participants: created, joined, found by token, deleted, and the
failed joins the guessing limits count. One transaction per method."""

from __future__ import annotations

import hmac
from collections.abc import Callable
from dataclasses import dataclass
from datetime import datetime, timedelta

from sqlalchemy import bindparam, delete, func, select, update
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from backend.eventstream.log import EventType, notify_replicas, record
from backend.eventstream.schemas import PresenceChanged
from backend.participants import Participant, Role
from backend.storage.database import Database
from backend.storage.erase import Eraser
from backend.storage.tables import JoinFailureRow, ParticipantRow, SessionRow

from .schemas import CodeRenewed

_CODE_DRAWS = 20  # codes drawn for a renewal before giving up

_sessions, _participants = SessionRow.__table__, ParticipantRow.__table__
# Every authenticated request runs it: built once.
_PARTICIPANT = (
    select(_participants.c.session_id, _participants.c.role, _participants.c.token_hash)
    .join(_sessions, _sessions.c.id == _participants.c.session_id)
    .where(
        _participants.c.token_hash == bindparam("token_hash"),
        _sessions.c.expires_at > bindparam("now"),
    )
)


@dataclass(frozen=True)
class JoinFailures:
    """Failed joins in the counting window: one client's (how many, the oldest, the
    newest) and everyone's."""

    client: int
    client_oldest: datetime | None
    client_newest: datetime | None
    overall: int


@dataclass(frozen=True)
class CodeRenewal:
    """When and how a join code is renewed: after this many failures naming it, by a code
    from ``new_code``, valid ``valid_for`` (at most until its session ends)."""

    after_failures: int
    new_code: Callable[[], str]
    valid_for: timedelta


class Pairings:
    def __init__(self, database: Database, eraser: Eraser) -> None:
        self.database = database
        self.eraser = eraser

    def create(
        self,
        session_id: str,
        *,
        starter_token_hash: str,
        join_code: str,
        now: datetime,
        expires_at: datetime,
        join_code_expires_at: datetime,
    ) -> bool:
        """A new session with the friend who started it; False if the join code is taken
        (draw another)."""
        try:
            with self.database.write() as tx:
                tx.add(
                    SessionRow(
                        id=session_id,
                        created_at=now,
                        expires_at=expires_at,
                        join_code=join_code,
                        join_code_expires_at=join_code_expires_at,
                        version=1,
                    )
                )
                tx.flush()
                tx.add(
                    ParticipantRow(
                        session_id=session_id,
                        role="starter",
                        token_hash=starter_token_hash,
                        joined_at=now,
                    )
                )
        except IntegrityError:
            return False
        return True

    def join(self, join_code: str, *, joiner_token_hash: str, now: datetime) -> str | None:
        """Claim a join code for the friend who joins: the session id, or None (unknown,
        used, expired).

        The code is cleared in the same statement that finds it, so it works once even when
        two phones race for it.
        """
        with self.database.write() as tx:
            claimed = tx.execute(
                update(SessionRow)
                .where(
                    SessionRow.join_code == join_code,
                    SessionRow.join_code_expires_at > now,
                    SessionRow.expires_at > now,
                )
                .values(join_code=None, join_code_expires_at=None, version=SessionRow.version + 1)
                .returning(SessionRow.id, SessionRow.version)
            ).first()
            if claimed is None:
                return None
            session_id, version = claimed
            tx.add(
                ParticipantRow(
                    session_id=session_id,
                    role="joiner",
                    token_hash=joiner_token_hash,
                    joined_at=now,
                )
            )
            joined = PresenceChanged(role="joiner", online=False, version=version)
            record(tx, session_id, EventType.JOINED, joined, now, locked=True)
        return str(session_id)

    def participant(self, token_hash: str, now: datetime) -> Participant | None:
        """Who holds this token, if its session is still alive.

        Found by the token's hash (an index lookup: its timing could tell at most how much
        of a hash matches a stored one, and a hash tells nothing of the token that makes
        it); the row found is then compared again in constant time, so that no comparison
        of this code depends on where two values first differ.
        """
        with self.database.query() as connection:
            row = connection.execute(_PARTICIPANT, {"token_hash": token_hash, "now": now}).first()
        if row is None or not hmac.compare_digest(row.token_hash, token_hash):
            return None
        role: Role = row.role
        return Participant(row.session_id, role)

    def delete(self, session_id: str) -> bool:
        """Delete the session and everything of it at once (photos, taps, events)."""
        with self.database.write() as tx:
            deleted = tx.execute(delete(SessionRow).where(SessionRow.id == session_id))
            notify_replicas(tx, session_id)
        if deleted.rowcount:  # type: ignore[attr-defined]
            self.eraser.deleted()
        return bool(deleted.rowcount)  # type: ignore[attr-defined]

    def delete_expired(self, now: datetime) -> list[str]:
        with self.database.write() as tx:
            gone = list(
                tx.scalars(
                    delete(SessionRow).where(SessionRow.expires_at <= now).returning(SessionRow.id)
                )
            )
            for session_id in gone:
                notify_replicas(tx, session_id)
        if gone:
            self.eraser.deleted()
        return gone

    # --- failed joins --------------------------------------------------------------------

    def join_failures(self, client: str, since: datetime) -> JoinFailures:
        """The failed joins after ``since``: ``client``'s and everyone's."""
        with self.database.read() as tx:
            mine = tx.execute(
                select(
                    func.count(),
                    func.min(JoinFailureRow.failed_at),
                    func.max(JoinFailureRow.failed_at),
                ).where(JoinFailureRow.client == client, JoinFailureRow.failed_at > since)
            ).one()
            overall = tx.scalar(
                select(func.count())
                .select_from(JoinFailureRow)
                .where(JoinFailureRow.failed_at > since)
            )
        return JoinFailures(int(mine[0]), mine[1], mine[2], int(overall or 0))

    def record_join_failure(
        self, client: str, code_range: tuple[str, str], now: datetime, renewal: CodeRenewal
    ) -> list[str]:
        """Count a failed join against ``client``, and against the live code whose search
        number it named (the codes in ``code_range``, both ends included: normally one, or
        none); a code that reaches ``renewal.after_failures`` is renewed. Returns the
        sessions whose code was renewed, whose starters' phones must show the new one."""
        with self.database.write() as tx:
            tx.add(JoinFailureRow(client=client, failed_at=now))
            charged = tx.execute(
                update(SessionRow)
                .where(
                    SessionRow.join_code.between(*code_range),
                    SessionRow.join_code_expires_at > now,
                    SessionRow.expires_at > now,
                )
                .values(join_code_failures=SessionRow.join_code_failures + 1)
                .returning(SessionRow.id, SessionRow.join_code_failures, SessionRow.expires_at)
            ).all()
            renewed = [row for row in charged if row.join_code_failures >= renewal.after_failures]
            for row in renewed:
                version = tx.scalar(
                    update(SessionRow)
                    .where(SessionRow.id == row.id)
                    .values(
                        join_code=_unused_code(tx, renewal.new_code),
                        join_code_expires_at=min(now + renewal.valid_for, row.expires_at),
                        join_code_failures=0,
                        join_code_renewals=SessionRow.join_code_renewals + 1,
                        version=SessionRow.version + 1,
                    )
                    .returning(SessionRow.version)
                )
                assert version is not None  # the row was just updated
                record(tx, row.id, EventType.CODE, CodeRenewed(version=version), now, locked=True)
        return [row.id for row in renewed]

    def forget_join_failures(self, before: datetime) -> None:
        """Delete failed joins at or before ``before`` (out of every window: client
        addresses are kept no longer than they count)."""
        with self.database.write() as tx:
            tx.execute(delete(JoinFailureRow).where(JoinFailureRow.failed_at <= before))


def _unused_code(tx: Session, new_code: Callable[[], str]) -> str | None:
    """A code from ``new_code`` that no session holds (10^8 codes: the first, nearly
    always); None if a few draws all are (the starter's phone then offers a new search)."""
    for _ in range(_CODE_DRAWS):
        code = new_code()
        if tx.scalar(select(SessionRow.id).where(SessionRow.join_code == code)) is None:
            return code
    return None
