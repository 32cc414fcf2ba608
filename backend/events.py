"""Server-sent events: "this changed" for the phones, which then fetch the state again.

Events live in the database (the store writes each one with its change), so a phone that
reconnects with ``Last-Event-ID`` gets what it missed, whichever replica it reaches. The
:class:`Notifier` wakes this process's streams as soon as a change is committed here;
changes made by other replicas are picked up by polling every ``event_poll_seconds``.
"""

from __future__ import annotations

import asyncio
import json
import threading
from collections import defaultdict
from typing import Any

# The types the phones react to.
EVENT_TYPES = ("joined", "photo", "taps", "result", "left", "expired")


class Notifier:
    """Wakes the event streams of a session, from any thread."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._waiters: dict[str, set[tuple[asyncio.AbstractEventLoop, asyncio.Event]]] = (
            defaultdict(set)
        )

    def notify(self, session_id: str) -> None:
        with self._lock:
            waiters = list(self._waiters.get(session_id, ()))
        for loop, event in waiters:
            loop.call_soon_threadsafe(event.set)

    async def wait(self, session_id: str, timeout: float) -> None:
        """Return when the session changes here, or after ``timeout`` seconds."""
        waiter = (asyncio.get_running_loop(), asyncio.Event())
        with self._lock:
            self._waiters[session_id].add(waiter)
        try:
            await asyncio.wait_for(waiter[1].wait(), timeout)
        except TimeoutError:
            pass
        finally:
            with self._lock:
                self._waiters[session_id].discard(waiter)
                if not self._waiters[session_id]:
                    del self._waiters[session_id]


def frame(event_id: int | None, type_: str, data: dict[str, Any]) -> str:
    """One event in the text/event-stream format (without an id: not to be resumed from)."""
    head = "" if event_id is None else f"id: {event_id}\n"
    return f"{head}event: {type_}\ndata: {json.dumps(data)}\n\n"


PING = ": ping\n\n"
# Ask EventSource to reconnect after 3 s when the connection drops.
RETRY = "retry: 3000\n\n"
