"""The store: what the session service reads and writes, one transaction per method.

Every change a phone should see bumps the session's version and writes its event in the
same transaction, so the version, the change and "this changed" never disagree; on
PostgreSQL that transaction also notifies every replica (``pg_notify``). Methods are
synchronous (SQLAlchemy); the service runs them off the event loop. Any of them raises
:class:`DatabaseUnavailableError` while the database cannot be reached.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from sqlalchemy import Engine, delete, func, select, update
from sqlalchemy.exc import IntegrityError, SQLAlchemyError
from sqlalchemy.orm import Session, sessionmaker

from backend.photos import StoredPhoto

from .database import DatabaseUnavailableError, unavailable
from .notifications import CHANNEL, ChangeListener
from .tables import EventRow, OverlayRow, ParticipantRow, PhotoRow, SessionRow

ROLES = ("seeker", "buddy")


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
class Event:
    id: int
    type: str
    data: dict[str, Any]


class Store:
    """All persistence of the service, behind intention-named methods."""

    def __init__(self, engine: Engine) -> None:
        self.engine = engine
        self._sessions = sessionmaker(engine, expire_on_commit=False)
        self._listener: ChangeListener | None = None

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
        """Who holds this token, if its session is still alive."""
        with self._read() as tx:
            row = tx.execute(
                select(ParticipantRow.session_id, ParticipantRow.role)
                .join(SessionRow, SessionRow.id == ParticipantRow.session_id)
                .where(ParticipantRow.token_hash == token_hash, SessionRow.expires_at > now)
            ).first()
        return None if row is None else Participant(row.session_id, row.role)

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
        return gone

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
