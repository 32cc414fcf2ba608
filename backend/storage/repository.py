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
import math
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from sqlalchemy import Engine, delete, func, select, update
from sqlalchemy.exc import DBAPIError, IntegrityError, SQLAlchemyError
from sqlalchemy.orm import Session, sessionmaker

from backend.photos import StoredPhoto

from .database import SQLITE_BUSY_TIMEOUT_MS, DatabaseUnavailableError, unavailable
from .notifications import CHANNEL, ChangeListener
from .tables import EventRow, JoinFailureRow, OverlayRow, ParticipantRow, PhotoRow, SessionRow

ROLES = ("seeker", "buddy")
# What VACUUM FULL rewrites: everything of a session, and the failed joins' addresses.
_ERASED_TABLES = ("sessions", "participants", "photos", "overlays", "events", "join_failures")
_CHECKPOINT_WAIT_MS = 1000
# VACUUM FULL waits this long for each table's lock (queueing requests behind it), then gives
# up until the next sweep.
_ERASE_LOCK_TIMEOUT = "5s"


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
    version: int
    result: dict[str, Any] | None
    result_version: int | None
    members: dict[str, Member]
    photos: dict[str, PhotoInfo]
    last_event_id: int


@dataclass(frozen=True)
class JoinFailures:
    """Failed joins in the counting window: one client's (how many, the oldest, the
    newest) and everyone's."""

    client: int
    client_oldest: datetime | None
    client_newest: datetime | None
    overall: int


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
        self._erase_pending = False
        self._erase_interval = erase_interval_seconds
        self._erased_at = -math.inf  # time.monotonic() of the last VACUUM FULL

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
    def _write(self) -> Iterator[Session]:
        """A transaction, committed at the end of the block (rolled back on an error)."""
        with _translated(), self._sessions.begin() as tx:
            yield tx

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
        with self._read() as tx:
            row = tx.execute(
                select(ParticipantRow.session_id, ParticipantRow.role, ParticipantRow.token_hash)
                .join(SessionRow, SessionRow.id == ParticipantRow.session_id)
                .where(ParticipantRow.token_hash == token_hash, SessionRow.expires_at > now)
            ).first()
        if row is None or not hmac.compare_digest(row.token_hash, token_hash):
            return None
        return Participant(row.session_id, row.role)

    def snapshot(self, session_id: str) -> Snapshot | None:
        with self._read() as tx:
            session = tx.get(SessionRow, session_id)
            if session is None:
                return None
            members = {
                p.role: Member(
                    p.role,
                    p.joined_at,
                    p.last_seen_at,
                    None if p.taps is None else json.loads(p.taps),
                )
                for p in tx.scalars(
                    select(ParticipantRow).where(ParticipantRow.session_id == session_id)
                )
            }
            photos = {
                row.role: PhotoInfo(row.width, row.height, row.scale)
                for row in tx.execute(
                    select(PhotoRow.role, PhotoRow.width, PhotoRow.height, PhotoRow.scale).where(
                        PhotoRow.session_id == session_id
                    )
                )
            }
            last_event = tx.scalar(
                select(func.max(EventRow.id)).where(EventRow.session_id == session_id)
            )
            return Snapshot(
                id=session.id,
                created_at=session.created_at,
                expires_at=session.expires_at,
                join_code=session.join_code,
                join_code_expires_at=session.join_code_expires_at,
                version=session.version,
                result=None if session.result is None else json.loads(session.result),
                result_version=session.result_version,
                members=members,
                photos=photos,
                last_event_id=last_event or 0,
            )

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
        self._erase_pending = True
        if self.engine.dialect.name == "sqlite":
            # Cheap with one process: at once. The deletion is done whatever happens here;
            # an erase that fails is the sweeper's to do again.
            with suppress(DatabaseUnavailableError):
                self.erase_deleted()

    def erase_deleted(self) -> bool:
        """Erase from the database's files the bytes of rows deleted since the last call
        (photos, overlays, taps, answers): True when nothing is left to erase, False when
        it must be tried again (the sweeper does, at its next round).

        SQLite overwrites deleted content with zeros as it deletes (``secure_delete``), but
        its write-ahead log still holds every page as it was written, photos included: the
        log is checkpointed into the database and truncated to nothing. That waits 1 s at
        most for readers on an older snapshot, and otherwise fails, to be tried again.

        PostgreSQL leaves a deleted row's bytes in its table's files, and VACUUM only marks
        that space free: VACUUM FULL copies each table without them into a new file and
        deletes the old one. It locks each table while copying it (requests touching it
        wait: about 1 s per 100 MB of photos kept), so it runs at most once per
        ``erase_interval_seconds``, after deletions only, giving up a table's lock after
        5 s. PostgreSQL's own write-ahead log (``pg_wal``, and any archive or backup of it)
        keeps the bytes until it is recycled: outside the app's reach.
        """
        if not self._erase_pending:
            return True
        postgresql = self.engine.dialect.name == "postgresql"
        if postgresql and time.monotonic() - self._erased_at < self._erase_interval:
            return False
        self._erase_pending = False  # a deletion from here on sets it again
        try:
            done = self._vacuum_full() if postgresql else self._checkpoint()
        except BaseException:
            self._erase_pending = True
            raise
        if postgresql:
            self._erased_at = time.monotonic()
        if not done:
            self._erase_pending = True
        return done

    def _checkpoint(self) -> bool:
        with _translated(), self.engine.connect() as connection:
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

    def record_join_failure(self, client: str, now: datetime) -> None:
        with self._write() as tx:
            tx.add(JoinFailureRow(client=client, failed_at=now))

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

    def put_taps(self, participant: Participant, taps: dict[str, Any], now: datetime) -> int:
        """Replace a participant's taps (the answer goes with the old ones); the new version."""
        sid, role = participant.session_id, participant.role
        with self._write() as tx:
            tx.execute(
                update(ParticipantRow)
                .where(ParticipantRow.session_id == sid, ParticipantRow.role == role)
                .values(taps=json.dumps(taps))
            )
            version = _bump(tx, sid)
            _event(tx, sid, "taps", {"role": role, "version": version}, now)
        return version

    def put_result(
        self, session_id: str, version: int, result: dict[str, Any] | None, now: datetime
    ) -> bool:
        """Record the answer computed for ``version``, unless the session has moved on since
        (then a newer computation records its own)."""
        with self._write() as tx:
            done = tx.execute(
                update(SessionRow)
                .where(SessionRow.id == session_id, SessionRow.version == version)
                .values(
                    result=None if result is None else json.dumps(result), result_version=version
                )
            )
            if not done.rowcount:  # type: ignore[attr-defined]
                return False
            _event(tx, session_id, "result", {"version": version}, now)
        return True

    # --- overlays ------------------------------------------------------------------------

    def overlay(self, session_id: str, role: str, fmt: str, version: int) -> bytes | None:
        with self._read() as tx:
            row = tx.get(OverlayRow, (session_id, role, fmt))
            return row.data if row is not None and row.version == version else None

    def put_overlay(self, session_id: str, role: str, fmt: str, version: int, data: bytes) -> None:
        try:
            with self._write() as tx:
                tx.merge(
                    OverlayRow(
                        session_id=session_id, role=role, format=fmt, version=version, data=data
                    )
                )
        except IntegrityError:
            pass  # the session was deleted meanwhile: nothing to keep

    # --- presence and events -------------------------------------------------------------

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
        with self._read() as tx:
            if tx.get(SessionRow, session_id) is None:
                return None
            rows = tx.execute(
                select(EventRow.id, EventRow.type, EventRow.data)
                .where(EventRow.session_id == session_id, EventRow.id > after)
                .order_by(EventRow.id)
            )
            return [Event(row.id, row.type, json.loads(row.data)) for row in rows]

    def healthy(self) -> bool:
        """The database answers, and changes from other replicas are being heard."""
        listening = self._listener is None or self._listener.listening
        with self._read() as tx:
            return tx.scalar(select(1)) == 1 and listening


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
