"""Server-sent events for one phone: each change with what the phone needs to show it,
pings, and presence. Served with FastAPI's own SSE support (``fastapi.sse``).

A stream subscribes to its session's wake-ups before reading anything, so a change
committed after that read wakes it; it replays what came after ``Last-Event-ID`` (a phone
that reconnects); it marks its phone online while connected and offline (telling the other
phone) when it goes. It outlives an outage of the database: it keeps pinging and reads
again when woken after it.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import AsyncGenerator, Callable
from contextlib import suppress
from dataclasses import dataclass, field
from typing import TypeVar

import anyio
from fastapi.sse import ServerSentEvent

from backend.clock import Clock
from backend.participants import Participant
from backend.storage.database import DatabaseUnavailableError

from .log import Event, EventLog, EventType
from .notifier import Notifier
from .presence import Presence
from .schemas import PresenceChanged, SessionEnded

# Ask EventSource to reconnect after 3 s when the connection drops.
RETRY_MS = 3000
PING = ServerSentEvent(comment="ping")
T = TypeVar("T")


def expired() -> ServerSentEvent:
    return ServerSentEvent(
        event=EventType.EXPIRED, data=SessionEnded(reason="The session ended.").model_dump()
    )


@dataclass(kw_only=True)
class EventStreams:
    """Every stream this process serves, and the phones they keep online."""

    log: EventLog
    presence: Presence
    notifier: Notifier
    clock: Clock
    keepalive_seconds: float
    poll_seconds: float
    # The phones whose streams this process holds (a phone may hold two for a moment,
    # reconnecting): kept online by :meth:`keep_online`, one write for all.
    _listening: Counter[Participant] = field(default_factory=Counter, init=False)

    async def events(
        self, participant: Participant, last_event_id: int | None
    ) -> AsyncGenerator[ServerSentEvent, None]:
        """The stream of one phone, until it disconnects (the server then cancels it) or
        the session ends. Reads when woken by a change (here or, on PostgreSQL, on any
        replica) and every ``poll_seconds`` in case a wake-up was lost; pings between."""
        session_id, role = participant.session_id, participant.role
        keepalive, poll = self.keepalive_seconds, self.poll_seconds
        with self.notifier.subscribe(session_id) as changed:
            try:
                await _in_thread(self.presence.seen, participant, self.clock())
                if last_event_id is None:
                    last_event_id = await _in_thread(self.log.last_event_id, session_id)
                expires_at = await _in_thread(self.presence.expires_at, session_id)
            except DatabaseUnavailableError:
                return  # gone since this request was authenticated: the phone retries
            yield ServerSentEvent(retry=RETRY_MS)
            if expires_at is None:
                yield expired()
                return
            after = last_event_id
            await self._presence(
                session_id, EventType.JOINED, PresenceChanged(role=role, online=True)
            )
            self._listening[participant] += 1
            try:
                pinged = time.monotonic()
                while True:
                    changed.clear()  # a change from now on wakes the wait below
                    events = await self._events_after(session_id, after)
                    polled = time.monotonic()
                    # Gone (deleted, swept), or past its time and about to be swept: it ended.
                    if events is None or self.clock() >= expires_at:
                        yield expired()
                        return
                    for event in events:
                        # Sent as written: parsing and writing its JSON again would
                        # change nothing the phone reads.
                        yield ServerSentEvent(
                            id=str(event.id), event=event.type, raw_data=event.json
                        )
                        after = event.id
                    # Until a change, the next poll or the end of the session; pinging.
                    while True:
                        now = time.monotonic()
                        if now - pinged >= keepalive:
                            yield PING
                            pinged = now
                        if now - polled >= poll or self.clock() >= expires_at:
                            break
                        if await changed.wait(min(pinged + keepalive, polled + poll) - now):
                            break
            finally:
                # Shielded: the client is gone and the stream is being cancelled.
                with anyio.CancelScope(shield=True):
                    await self._hang_up(participant)

    def keep_online(self) -> None:
        """Mark every phone listening here as seen now (every ``online_seconds / 3``: a
        listening phone stays online; one that stops being heard goes offline)."""
        if listening := list(self._listening):
            self.presence.seen_all(listening, self.clock())

    def watch(self, after: int | None) -> int:
        """Wake the streams of sessions that another process changed or deleted since event
        ``after`` (None: start watching now); the newest event id. For several worker
        processes on one SQLite file, which have no LISTEN/NOTIFY; a change made here wakes
        its streams once more, which then find nothing new."""
        newest, changed = self.log.changes_since(after, self.notifier.watched())
        for session_id in changed:
            self.notifier.notify(session_id)
        return newest

    async def _hang_up(self, participant: Participant) -> None:
        """A stream of ``participant`` ended: offline, and the other phone told, unless
        another stream of it is still open here (a phone that reconnected)."""
        self._listening[participant] -= 1
        if self._listening[participant] > 0:
            return
        del self._listening[participant]
        with suppress(DatabaseUnavailableError):
            await _in_thread(self.presence.seen, participant, None)
            await self._presence(
                participant.session_id,
                EventType.LEFT,
                PresenceChanged(role=participant.role, online=False),
            )

    async def _events_after(self, session_id: str, after: int) -> list[Event] | None:
        """The session's events after ``after`` (None: it is gone); none while the database
        is unavailable (when it is back, every stream is woken to read again)."""
        try:
            return await _in_thread(self.log.events_after, session_id, after)
        except DatabaseUnavailableError:
            return []

    async def _presence(self, session_id: str, type_: EventType, data: PresenceChanged) -> None:
        """Tell the other phone this one came or went (skipped while the database is away:
        presence also shows in the state)."""
        with suppress(DatabaseUnavailableError):
            await _in_thread(self.log.publish, session_id, type_, data, self.clock())
        self.notifier.notify(session_id)


async def _in_thread(function: Callable[..., T], *args: object) -> T:
    return await anyio.to_thread.run_sync(lambda: function(*args))
