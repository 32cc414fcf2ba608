"""PostgreSQL's LISTEN/NOTIFY: "this session changed", from whichever replica changed it.

Every transaction that writes an event or deletes a session sends ``pg_notify(CHANNEL,
session_id)`` (:func:`.log.record`, :func:`.log.notify_replicas`); PostgreSQL delivers it
at commit, so never before the change is visible. Each replica runs one
:class:`ChangeListener`, which hears them all on a connection of its own.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from contextlib import suppress

import psycopg
from sqlalchemy.engine import URL

log = logging.getLogger(__name__)

CHANNEL = "buddy_events"
# Reconnecting after a lost connection: first at once, then waiting longer, up to this.
MAX_BACKOFF_SECONDS = 2.0


class ChangeListener:
    """``LISTEN``, as an asyncio task (:meth:`run`): ``changed(session_id)`` for each
    notification.

    Survives the server going away: it reconnects with backoff, and after each
    (re)connection calls ``missed()``, since notifications sent meanwhile are lost.
    """

    def __init__(
        self, url: URL, changed: Callable[[str], None], missed: Callable[[], None]
    ) -> None:
        # libpq's own form of the URL: the driver name is SQLAlchemy's, not libpq's.
        self._conninfo = url.set(drivername="postgresql").render_as_string(hide_password=False)
        self._changed = changed
        self._missed = missed
        self._listening = asyncio.Event()

    @property
    def listening(self) -> bool:
        """Connected and listening: no notification goes unheard."""
        return self._listening.is_set()

    async def started(self, timeout: float) -> None:
        """Return once listening, or after ``timeout`` seconds."""
        with suppress(TimeoutError):
            await asyncio.wait_for(self._listening.wait(), timeout)

    async def run(self) -> None:
        """Listen until cancelled."""
        backoff = 0.0
        while True:
            try:
                await self._listen()
            except Exception as error:  # never dies: the replica would go deaf for good
                if self.listening or backoff == 0.0:  # a new outage: said once, retried soon
                    log.warning("listening for changes failed (%s); reconnecting", error)
                    backoff = 0.0
                backoff = min(max(2 * backoff, 0.1), MAX_BACKOFF_SECONDS)
            finally:
                self._listening.clear()
            await asyncio.sleep(backoff)

    async def _listen(self) -> None:
        # TCP keepalives: a server that vanished without closing the connection is noticed.
        async with await psycopg.AsyncConnection.connect(
            self._conninfo,
            autocommit=True,
            connect_timeout=5,
            keepalives=1,
            keepalives_idle=10,
            keepalives_interval=5,
            keepalives_count=3,
        ) as connection:
            await connection.execute(f"LISTEN {CHANNEL}")
            self._listening.set()
            self._missed()  # after LISTEN: any change from now on is notified as well
            async for notification in connection.notifies():
                self._changed(notification.payload)
