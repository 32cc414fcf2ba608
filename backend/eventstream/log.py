"""The event log: each change as a row of the events table, written in the transaction of
the change it announces, with what the other phone needs to show it; read by the streams.

Events live in the database, so a phone that reconnects with ``Last-Event-ID`` gets what it
missed, whichever replica it reaches; ids are never reused (migration 0004), so a reader
that has looked past an id never needs to look there again.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime
from enum import StrEnum
from typing import Any

from pydantic import BaseModel
from sqlalchemy import bindparam, func, insert, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from backend.storage.database import Database
from backend.storage.tables import EventRow, SessionRow, core

from .listener import CHANNEL


class EventType(StrEnum):
    """What a phone is told (each type's data: ``backend.sessions.schemas.SessionEvents``)."""

    JOINED = "joined"  # a phone opened its stream (or joined the search)
    CODE = "code"  # the join code was renewed after wrong guesses
    PHOTO = "photo"
    TAPS = "taps"
    ANSWER = "answer"
    LEFT = "left"  # a phone's stream closed
    EXPIRED = "expired"  # the session ended (deleted, or its time is up): sent, never stored


@dataclass(frozen=True)
class Event:
    id: int
    type: str
    json: str  # its data as written (JSON): what the stream sends, as is

    @property
    def data(self) -> dict[str, Any]:
        data: dict[str, Any] = json.loads(self.json)
        return data


_sessions, _events = core(SessionRow), core(EventRow)
# The hot reads, built once (building a statement costs more than running it on SQLite).
_EXISTING = select(_sessions.c.id).where(_sessions.c.id.in_(bindparam("ids", expanding=True)))
_NEWEST_EVENT = select(func.max(_events.c.id))
_NEW_EVENTS = (
    select(_events.c.session_id, func.max(_events.c.id).label("newest"))
    .where(_events.c.id > bindparam("after"))
    .group_by(_events.c.session_id)
)
_LAST_EVENT = select(func.max(_events.c.id)).where(_events.c.session_id == bindparam("session_id"))
_LOCK_SESSION = (
    select(_sessions.c.id)
    .where(_sessions.c.id == bindparam("session_id"))
    .with_for_update(key_share=True)
)
# (Bound names other than the columns': SQLAlchemy keeps those for the values.)
_ADD_EVENT = insert(_events).values(
    session_id=bindparam("of"),
    type=bindparam("kind"),
    data=bindparam("told"),
    created_at=bindparam("at"),
)
# PostgreSQL: the event's insert also notifies the replicas (at commit), in its one round trip.
_ADD_EVENT_NOTIFYING = _ADD_EVENT.returning(func.pg_notify(CHANNEL, _events.c.session_id))
# One query for a stream's every wake: the session (no row: gone) with its events after an
# id (one row of nulls: none yet).
_EVENTS_AFTER = (
    select(_events.c.id, _events.c.type, _events.c.data)
    .select_from(_sessions)
    .outerjoin(
        _events,
        (_events.c.session_id == _sessions.c.id) & (_events.c.id > bindparam("after")),
    )
    .where(_sessions.c.id == bindparam("session_id"))
    .order_by(_events.c.id)
)


def record(
    tx: Session,
    session_id: str,
    type_: EventType,
    data: BaseModel,
    now: datetime,
    *,
    locked: bool = False,
) -> None:
    """Write an event in ``tx``, and tell every replica's streams of its session.

    The session's row is locked first, unless ``locked`` (the transaction changed it
    already): then the events of a session commit in the order of their ids, and a stream
    that has read up to an id never misses a smaller one committed later by a concurrent
    writer. Core statements: the hottest write path, with no ORM work per event.
    """
    if not locked:
        tx.execute(_LOCK_SESSION, {"session_id": session_id})
    event = {"of": session_id, "kind": type_, "told": data.model_dump_json(), "at": now}
    if _first_notice(tx, session_id):
        tx.execute(_ADD_EVENT_NOTIFYING, event).close()
    else:
        tx.execute(_ADD_EVENT, event)


def notify_replicas(tx: Session, session_id: str) -> None:
    """PostgreSQL: wake every replica's streams of this session, at commit."""
    if _first_notice(tx, session_id):
        tx.execute(select(func.pg_notify(CHANNEL, session_id)))


def _first_notice(tx: Session, session_id: str) -> bool:
    """Whether to notify the replicas of this session in ``tx``: on PostgreSQL, once per
    transaction (one notification wakes the streams to read all its events)."""
    if tx.get_bind().dialect.name != "postgresql":
        return False
    notified: set[str] = tx.info.setdefault("notified", set())
    if session_id in notified:
        return False
    notified.add(session_id)
    return True


class EventLog:
    """What the streams read, and the events that change no state (presence)."""

    def __init__(self, database: Database) -> None:
        self.database = database

    def publish(self, session_id: str, type_: EventType, data: BaseModel, now: datetime) -> None:
        """An event with no change of state (a phone came or went)."""
        try:
            with self.database.write() as tx:
                record(tx, session_id, type_, data, now)
        except IntegrityError:
            pass  # the session is gone

    def last_event_id(self, session_id: str) -> int:
        """The id of the session's newest event (0: none yet): where a new stream starts."""
        with self.database.query() as connection:
            return int(connection.scalar(_LAST_EVENT, {"session_id": session_id}) or 0)

    def events_after(self, session_id: str, after: int) -> list[Event] | None:
        """Events of a session newer than ``after``; None when the session is gone."""
        with self.database.query() as connection:
            rows = connection.execute(
                _EVENTS_AFTER, {"session_id": session_id, "after": after}
            ).all()
        if not rows:
            return None
        return [Event(row.id, row.type, row.data) for row in rows if row.id is not None]

    def changes_since(self, after: int | None, watched: Sequence[str]) -> tuple[int, set[str]]:
        """What other processes may have changed: the newest event id, and the sessions
        with an event newer than ``after`` (None: the first look, nothing is new) or, of
        ``watched``, deleted."""
        with self.database.query() as connection:
            if after is None:
                return int(connection.scalar(_NEWEST_EVENT) or 0), set()
            changed = {
                row.session_id: row.newest
                for row in connection.execute(_NEW_EVENTS, {"after": after})
            }
            gone = set(watched) - set(connection.scalars(_EXISTING, {"ids": list(watched)}))
        return max(changed.values(), default=after), set(changed) | gone
