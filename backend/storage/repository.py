"""The store: what the session service reads and writes, one transaction per method.

Every change a phone should see bumps the session's version and writes its event in the
same transaction, so the version, the change and "this changed" never disagree; on
PostgreSQL that transaction also notifies every replica (``pg_notify``). Methods are
synchronous (SQLAlchemy); the service runs them off the event loop. Any of them raises
:class:`DatabaseUnavailableError` while the database cannot be reached.
"""

from __future__ import annotations

import hmac
import json
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager, nullcontext
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any

from sqlalchemy import Connection, Engine, bindparam, delete, func, select, tuple_, update
from sqlalchemy.exc import DBAPIError, IntegrityError, SQLAlchemyError
from sqlalchemy.orm import Session, sessionmaker

from backend.photos import StoredPhoto

from .database import (
    SQLITE_BUSY_TIMEOUT_MS,
    DatabaseUnavailableError,
    WriterLock,
    sqlite_file,
    unavailable,
)
from .erasing import EraseTurn
from .notifications import CHANNEL, ChangeListener
from .tables import EventRow, JoinFailureRow, ParticipantRow, PhotoRow, SessionRow

ROLES = ("seeker", "buddy")
# What VACUUM FULL rewrites: everything of a session, and the failed joins' addresses.
_ERASED_TABLES = ("sessions", "participants", "photos", "events", "join_failures")
_CHECKPOINT_WAIT_MS = 1000
# VACUUM FULL waits this long for each table's lock (queueing requests behind it), then gives
# up until the next sweep.
_ERASE_LOCK_TIMEOUT = "5s"
_CODE_DRAWS = 20  # codes drawn for a renewal before giving up
_SEEN_BATCH = 500  # participants per statement (SQLite binds at most 32766 values)

# The hot reads, built once (building a statement costs more than running it on SQLite).
_sessions, _participants, _photos, _events = (
    row.__table__ for row in (SessionRow, ParticipantRow, PhotoRow, EventRow)
)
_SNAPSHOT = (
    select(
        _sessions.c.id,
        _sessions.c.created_at,
        _sessions.c.expires_at,
        _sessions.c.join_code,
        _sessions.c.join_code_expires_at,
        _sessions.c.join_code_renewals,
        _sessions.c.version,
        _sessions.c.result,
        _sessions.c.result_version,
        _participants.c.role,
        _participants.c.joined_at,
        _participants.c.last_seen_at,
        _participants.c.taps,
        _photos.c.width,
        _photos.c.height,
        _photos.c.scale,
    )
    .join(_participants, _participants.c.session_id == _sessions.c.id)
    .outerjoin(
        _photos,
        (_photos.c.session_id == _participants.c.session_id)
        & (_photos.c.role == _participants.c.role),
    )
    .where(_sessions.c.id == bindparam("session_id"))
)
_PARTICIPANT = (
    select(_participants.c.session_id, _participants.c.role, _participants.c.token_hash)
    .join(_sessions, _sessions.c.id == _participants.c.session_id)
    .where(
        _participants.c.token_hash == bindparam("token_hash"),
        _sessions.c.expires_at > bindparam("now"),
    )
)
_ALIVE = select(_sessions.c.id).where(_sessions.c.id == bindparam("session_id"))
_EXISTING = select(_sessions.c.id).where(_sessions.c.id.in_(bindparam("ids", expanding=True)))
_NEWEST_EVENT = select(func.max(_events.c.id))
_NEW_EVENTS = (
    select(_events.c.session_id, func.max(_events.c.id).label("newest"))
    .where(_events.c.id > bindparam("after"))
    .group_by(_events.c.session_id)
)
_LAST_EVENT = select(func.max(_events.c.id)).where(_events.c.session_id == bindparam("session_id"))
_EVENTS_AFTER = (
    select(_events.c.id, _events.c.type, _events.c.data)
    .where(_events.c.session_id == bindparam("session_id"), _events.c.id > bindparam("after"))
    .order_by(_events.c.id)
)


@dataclass(frozen=True)
class Participant:
    session_id: str
    role: str


@dataclass(frozen=True)
class PhotoInfo:
    width: int
    height: int
    scale: float


@dataclass(frozen=True)
class Member:
    """A participant as the others see them."""

    role: str
    joined_at: datetime
    last_seen_at: datetime | None
    taps: dict[str, Any] | None


@dataclass(frozen=True)
class Snapshot:
    """Everything of a session but the photos' bytes, read in one transaction."""

    id: str
    created_at: datetime
    expires_at: datetime
    join_code: str | None
    join_code_expires_at: datetime | None
    join_code_renewals: int
    version: int
    result: dict[str, Any] | None
    result_version: int | None
    members: dict[str, Member]
    photos: dict[str, PhotoInfo]


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


@dataclass(frozen=True)
class Event:
    id: int
    type: str
    data: dict[str, Any]


class Store:
    """All persistence of the service, behind intention-named methods."""

    def __init__(self, engine: Engine, erase_interval_seconds: float = 0.0) -> None:
        self.engine = engine
        self._sessions = sessionmaker(engine, expire_on_commit=False)
        self._listener: ChangeListener | None = None
        path = sqlite_file(engine)
        self._writer = None if path is None else WriterLock(path)
        self._erase_pending = False
        # PostgreSQL: one VACUUM FULL per erase interval for all replicas (erasing.py).
        self._erase_turn = EraseTurn(engine, erase_interval_seconds)

    def change_listener(
        self, changed: Callable[[str], None], missed: Callable[[], None]
    ) -> ChangeListener | None:
        """What makes ``changed(session_id)`` be called whenever any replica changes a
        session, and ``missed()`` when some such calls may have been lost (an outage): on
        PostgreSQL a LISTEN/NOTIFY listener for the caller to run as a task. None with
        SQLite (one process: the service's own notifications and polling suffice)."""
        if self.engine.dialect.name == "postgresql" and self._listener is None:
            self._listener = ChangeListener(self.engine.url, changed, missed)
        return self._listener

    @contextmanager
    def _read(self) -> Iterator[Session]:
        with _translated(), self._sessions() as tx:
            yield tx

    @contextmanager
    def _query(self) -> Iterator[Connection]:
        """A plain connection for the hot reads, which run prepared Core statements: no ORM
        work per call."""
        with _translated(), self.engine.connect() as connection:
            yield connection

    @contextmanager
    def _write(self) -> Iterator[Session]:
        """A transaction, committed at the end of the block (rolled back on an error)."""
        with self._writing(), _translated(), self._sessions.begin() as tx:
            yield tx

    def _writing(self) -> AbstractContextManager[None]:
        """Holds the writer lock of a SQLite file (PostgreSQL takes row locks itself)."""
        return nullcontext() if self._writer is None else self._writer.held()

    # --- sessions ------------------------------------------------------------------------

    def create(
        self,
        session_id: str,
        *,
        seeker_token_hash: str,
        join_code: str,
        now: datetime,
        expires_at: datetime,
        join_code_expires_at: datetime,
    ) -> bool:
        """A new session with its seeker; False if the join code is taken (draw another)."""
        try:
            with self._write() as tx:
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
                        role="seeker",
                        token_hash=seeker_token_hash,
                        joined_at=now,
                    )
                )
        except IntegrityError:
            return False
        return True

    def join(self, join_code: str, *, buddy_token_hash: str, now: datetime) -> str | None:
        """Claim a join code for the buddy: the session id, or None (unknown, used, expired).

        The code is cleared in the same statement that finds it, so it works once even when
        two phones race for it.
        """
        with self._write() as tx:
            session_id = tx.scalar(
                update(SessionRow)
                .where(
                    SessionRow.join_code == join_code,
                    SessionRow.join_code_expires_at > now,
                    SessionRow.expires_at > now,
                )
                .values(join_code=None, join_code_expires_at=None, version=SessionRow.version + 1)
                .returning(SessionRow.id)
            )
            if session_id is None:
                return None
            tx.add(
                ParticipantRow(
                    session_id=session_id, role="buddy", token_hash=buddy_token_hash, joined_at=now
                )
            )
            _event(tx, session_id, "joined", {"role": "buddy"}, now)
        return session_id

    def participant(self, token_hash: str, now: datetime) -> Participant | None:
        """Who holds this token, if its session is still alive.

        Found by the token's hash (an index lookup: its timing could tell at most how much
        of a hash matches a stored one, and a hash tells nothing of the token that makes
        it); the row found is then compared again in constant time, so that no comparison
        of this code depends on where two values first differ.
        """
        with self._query() as connection:
            row = connection.execute(_PARTICIPANT, {"token_hash": token_hash, "now": now}).first()
        if row is None or not hmac.compare_digest(row.token_hash, token_hash):
            return None
        return Participant(row.session_id, row.role)

    def snapshot(self, session_id: str) -> Snapshot | None:
        """The session as the phones see it, in one statement (the hottest read: every state
        fetch and change reads it)."""
        with self._query() as connection:
            rows = connection.execute(_SNAPSHOT, {"session_id": session_id}).all()
        if not rows:
            return None
        first = rows[0]
        return Snapshot(
            id=first.id,
            created_at=first.created_at,
            expires_at=first.expires_at,
            join_code=first.join_code,
            join_code_expires_at=first.join_code_expires_at,
            join_code_renewals=first.join_code_renewals,
            version=first.version,
            result=None if first.result is None else json.loads(first.result),
            result_version=first.result_version,
            members={
                row.role: Member(
                    row.role,
                    row.joined_at,
                    row.last_seen_at,
                    None if row.taps is None else json.loads(row.taps),
                )
                for row in rows
            },
            photos={
                row.role: PhotoInfo(row.width, row.height, row.scale)
                for row in rows
                if row.width is not None
            },
        )

    def last_event_id(self, session_id: str) -> int:
        """The id of the session's newest event (0: none yet): where a new stream starts."""
        with self._query() as connection:
            return int(connection.scalar(_LAST_EVENT, {"session_id": session_id}) or 0)

    def delete(self, session_id: str) -> bool:
        """Delete the session and everything of it at once (photos, taps, events)."""
        with self._write() as tx:
            deleted = tx.execute(delete(SessionRow).where(SessionRow.id == session_id))
            _notify(tx, session_id)
        if deleted.rowcount:  # type: ignore[attr-defined]
            self._deleted()
        return bool(deleted.rowcount)  # type: ignore[attr-defined]

    def delete_expired(self, now: datetime) -> list[str]:
        with self._write() as tx:
            gone = list(
                tx.scalars(
                    delete(SessionRow).where(SessionRow.expires_at <= now).returning(SessionRow.id)
                )
            )
            for session_id in gone:
                _notify(tx, session_id)
        if gone:
            self._deleted()
        return gone

    # --- erasing what deleted rows leave behind ------------------------------------------

    def _deleted(self) -> None:
        """Something was deleted: its bytes are for :meth:`erase_deleted` to erase (the
        eraser does, within seconds, off the request)."""
        self._erase_pending = True

    def erase_deleted(self) -> bool:
        """Erase from the database's files the bytes of rows deleted since the last call
        (photos, taps, answers): True when nothing is left to erase, False when
        it must be tried again (the sweeper does, at its next round).

        SQLite overwrites deleted content with zeros as it deletes (``secure_delete``), but
        its write-ahead log still holds every page as it was written, photos included: the
        log is checkpointed into the database and truncated to nothing. That waits 1 s at
        most for readers on an older snapshot, and otherwise fails, to be tried again.

        PostgreSQL leaves a deleted row's bytes in its table's files, and VACUUM only marks
        that space free: VACUUM FULL copies each table without them into a new file and
        deletes the old one. It locks each table while copying it (requests touching it
        wait: the load benchmark reports how long), so it runs at most once per
        ``erase_interval_seconds`` for all replicas together (the one that erases takes the
        turn: erasing.py), after deletions only, giving up a table's lock after 5 s.
        PostgreSQL's own write-ahead log (``pg_wal``, and any archive or backup of it)
        keeps the bytes until it is recycled: outside the app's reach.
        """
        postgresql = self.engine.dialect.name == "postgresql"
        if postgresql:
            with _translated():
                self._erase_turn.end_if_over()
        if not self._erase_pending:
            return True
        if postgresql:
            with _translated():
                if not self._erase_turn.take():  # erased within the interval, here or not
                    return False
        self._erase_pending = False  # a deletion from here on sets it again
        try:
            done = self._vacuum_full() if postgresql else self._checkpoint()
        except BaseException:
            self._erase_pending = True
            raise
        if not done:
            self._erase_pending = True
        return done

    def _checkpoint(self) -> bool:
        # As a writer: the checkpoint blocks writers anyway, who wait in line meanwhile.
        with self._writing(), _translated(), self.engine.connect() as connection:
            autocommit = connection.execution_options(isolation_level="AUTOCOMMIT")
            # Waits for readers 1 s, not the usual 30: "Delete now" answers at once, and a
            # checkpoint that could not finish is done by the next sweep.
            autocommit.exec_driver_sql(f"PRAGMA busy_timeout={_CHECKPOINT_WAIT_MS}")
            try:
                busy, _, _ = autocommit.exec_driver_sql("PRAGMA wal_checkpoint(TRUNCATE)").one()
            finally:
                autocommit.exec_driver_sql(f"PRAGMA busy_timeout={SQLITE_BUSY_TIMEOUT_MS}")
        return busy == 0

    def _vacuum_full(self) -> bool:
        with _translated(), self.engine.connect() as connection:
            autocommit = connection.execution_options(isolation_level="AUTOCOMMIT")
            autocommit.exec_driver_sql(f"SET lock_timeout = '{_ERASE_LOCK_TIMEOUT}'")
            try:
                autocommit.exec_driver_sql(f"VACUUM (FULL) {', '.join(_ERASED_TABLES)}")
            except DBAPIError as error:
                if getattr(error.orig, "sqlstate", None) == "55P03":  # lock_not_available
                    return False
                raise
            finally:
                autocommit.exec_driver_sql("RESET lock_timeout")
        return True

    # --- failed joins --------------------------------------------------------------------

    def join_failures(self, client: str, since: datetime) -> JoinFailures:
        """The failed joins after ``since``: ``client``'s and everyone's."""
        with self._read() as tx:
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
        sessions whose code was renewed, whose seekers' phones must show the new one."""
        with self._write() as tx:
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
                tx.execute(
                    update(SessionRow)
                    .where(SessionRow.id == row.id)
                    .values(
                        join_code=_unused_code(tx, renewal.new_code),
                        join_code_expires_at=min(now + renewal.valid_for, row.expires_at),
                        join_code_failures=0,
                        join_code_renewals=SessionRow.join_code_renewals + 1,
                        version=SessionRow.version + 1,
                    )
                )
                _event(tx, row.id, "code", {"renewed": True}, now)
        return [row.id for row in renewed]

    def forget_join_failures(self, before: datetime) -> None:
        """Delete failed joins at or before ``before`` (out of every window: client
        addresses are kept no longer than they count)."""
        with self._write() as tx:
            tx.execute(delete(JoinFailureRow).where(JoinFailureRow.failed_at <= before))

    # --- photos and taps -----------------------------------------------------------------

    def put_photo(self, participant: Participant, photo: StoredPhoto, now: datetime) -> int:
        """Store (or replace) a participant's photo. Its old taps meant points of the old
        photo, so they are cleared, and so is the answer. Returns the new version."""
        sid, role = participant.session_id, participant.role
        with self._write() as tx:
            # The version first: it locks the session, so a second upload of the same photo
            # waits here and then finds this one's row instead of inserting it twice.
            version = _bump(tx, sid)
            tx.merge(
                PhotoRow(
                    session_id=sid,
                    role=role,
                    data=photo.data,
                    width=photo.width,
                    height=photo.height,
                    scale=photo.scale,
                    uploaded_at=now,
                )
            )
            tx.execute(
                update(ParticipantRow)
                .where(ParticipantRow.session_id == sid, ParticipantRow.role == role)
                .values(taps=None)
            )
            _event(tx, sid, "photo", {"role": role, "version": version}, now)
        return version

    def photo(self, session_id: str, role: str) -> StoredPhoto | None:
        with self._read() as tx:
            row = tx.get(PhotoRow, (session_id, role))
            if row is None:
                return None
            return StoredPhoto(data=row.data, width=row.width, height=row.height, scale=row.scale)

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
        with self._write() as tx:
            tx.execute(
                update(ParticipantRow)
                .where(ParticipantRow.session_id == sid, ParticipantRow.role == role)
                .values(taps=json.dumps(taps))
            )
            version = _bump(tx, sid)
            _event(tx, sid, "taps", {"role": role, "version": version}, now)
            answered = answer is not None and answer[0] + 1 == version
            if answer is not None and answered:
                _record_result(tx, sid, version, answer[1], now)
        return version, answered

    def put_result(
        self, session_id: str, version: int, result: dict[str, Any] | None, now: datetime
    ) -> bool:
        """Record the answer computed for ``version``, unless the session has moved on since
        (then a newer computation records its own)."""
        with self._write() as tx:
            return _record_result(tx, session_id, version, result, now)

    # --- presence and events -------------------------------------------------------------

    def seen_all(self, participants: Sequence[Participant], when: datetime) -> None:
        """Mark all these participants' event streams alive at ``when``, in one write."""
        keys = [(p.session_id, p.role) for p in participants]
        with self._write() as tx:
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

    def seen(self, participant: Participant, when: datetime | None) -> None:
        """Mark a participant's event stream alive at ``when`` (None: gone offline)."""
        with self._write() as tx:
            tx.execute(
                update(ParticipantRow)
                .where(
                    ParticipantRow.session_id == participant.session_id,
                    ParticipantRow.role == participant.role,
                )
                .values(last_seen_at=when)
            )

    def publish(self, session_id: str, type_: str, data: dict[str, Any], now: datetime) -> None:
        """An event with no change of state (presence)."""
        try:
            with self._write() as tx:
                _event(tx, session_id, type_, data, now)
        except IntegrityError:
            pass  # the session is gone

    def events_after(self, session_id: str, after: int) -> list[Event] | None:
        """Events of a session newer than ``after``; None when the session is gone."""
        with self._query() as connection:
            if connection.scalar(_ALIVE, {"session_id": session_id}) is None:
                return None
            rows = connection.execute(_EVENTS_AFTER, {"session_id": session_id, "after": after})
            return [Event(row.id, row.type, json.loads(row.data)) for row in rows]

    def changes_since(self, after: int | None, watched: Sequence[str]) -> tuple[int, set[str]]:
        """What other processes may have changed: the newest event id, and the sessions
        with an event newer than ``after`` (None: the first look, nothing is new) or, of
        ``watched``, deleted."""
        with self._query() as connection:
            if after is None:
                return int(connection.scalar(_NEWEST_EVENT) or 0), set()
            changed = {
                row.session_id: row.newest
                for row in connection.execute(_NEW_EVENTS, {"after": after})
            }
            gone = set(watched) - set(connection.scalars(_EXISTING, {"ids": list(watched)}))
        return max(changed.values(), default=after), set(changed) | gone

    def healthy(self) -> bool:
        """The database answers, and changes from other replicas are being heard."""
        listening = self._listener is None or self._listener.listening
        with self._read() as tx:
            return tx.scalar(select(1)) == 1 and listening


def _record_result(
    tx: Session, session_id: str, version: int, result: dict[str, Any] | None, now: datetime
) -> bool:
    """The answer for ``version`` and its event, if the session is still at that version."""
    done = tx.execute(
        update(SessionRow)
        .where(SessionRow.id == session_id, SessionRow.version == version)
        .values(result=None if result is None else json.dumps(result), result_version=version)
    )
    if not done.rowcount:  # type: ignore[attr-defined]
        return False
    _event(tx, session_id, "result", {"version": version}, now)
    return True


def _unused_code(tx: Session, new_code: Callable[[], str]) -> str | None:
    """A code from ``new_code`` that no session holds (10^8 codes: the first, nearly
    always); None if a few draws all are (the seeker's phone then offers a new search)."""
    for _ in range(_CODE_DRAWS):
        code = new_code()
        if tx.scalar(select(SessionRow.id).where(SessionRow.join_code == code)) is None:
            return code
    return None


def _bump(tx: Session, session_id: str) -> int:
    """A new version; the answer was for the old one, so it goes."""
    version = tx.scalar(
        update(SessionRow)
        .where(SessionRow.id == session_id)
        .values(version=SessionRow.version + 1, result=None, result_version=None)
        .returning(SessionRow.version)
    )
    assert version is not None  # the caller holds a valid token of this session
    return int(version)


def _event(tx: Session, session_id: str, type_: str, data: dict[str, Any], now: datetime) -> None:
    """Write an event, and tell every replica's streams of its session.

    The session's row is locked first (a no-op where the transaction changed it already):
    then the events of a session commit in the order of their ids, and a stream that has
    read up to an id never misses a smaller one committed later by a concurrent writer.
    """
    tx.execute(
        select(SessionRow.id).where(SessionRow.id == session_id).with_for_update(key_share=True)
    )
    tx.add(EventRow(session_id=session_id, type=type_, data=json.dumps(data), created_at=now))
    _notify(tx, session_id)


def _notify(tx: Session, session_id: str) -> None:
    """PostgreSQL: wake every replica's streams of this session, at commit."""
    if tx.get_bind().dialect.name == "postgresql":
        tx.execute(select(func.pg_notify(CHANNEL, session_id)))


@contextmanager
def _translated() -> Iterator[None]:
    """An unreachable database as :class:`DatabaseUnavailableError`; other errors unchanged."""
    try:
        yield
    except SQLAlchemyError as error:
        if unavailable(error):
            raise DatabaseUnavailableError(str(error).splitlines()[0]) from error
        raise
