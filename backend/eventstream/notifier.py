"""Waking this process's event streams when a session changes, from any thread.

A change committed here wakes its streams at once; with PostgreSQL, the replicas' changes
arrive by LISTEN/NOTIFY (:mod:`.listener`); with SQLite, other worker processes' changes
are found by the watcher (:mod:`.watcher`). Streams also re-read the event table every
``event_poll_seconds``, in case a wake-up was lost.
"""

from __future__ import annotations

import asyncio
import threading
from collections import defaultdict
from collections.abc import Iterator
from contextlib import contextmanager, suppress


class Wakeup:
    """One stream's "something changed" flag, set from any thread."""

    def __init__(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._changed = asyncio.Event()

    def set(self) -> None:
        self._loop.call_soon_threadsafe(self._changed.set)

    def clear(self) -> None:
        """Before reading: a change from now on makes the next :meth:`wait` return."""
        self._changed.clear()

    async def wait(self, timeout: float) -> bool:
        """Whether something changed since :meth:`clear`, waiting at most ``timeout`` s."""
        with suppress(TimeoutError):
            await asyncio.wait_for(self._changed.wait(), max(timeout, 0))
        return self._changed.is_set()


class Notifier:
    """Wakes the event streams of a session, from any thread.

    A stream subscribes for its whole life (:meth:`subscribe`), so a change that comes
    while it is busy reading or sending is not lost: its flag stays set until it waits.
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._wakeups: dict[str, set[Wakeup]] = defaultdict(set)

    def notify(self, session_id: str) -> None:
        with self._lock:
            wakeups = list(self._wakeups.get(session_id, ()))
        for wakeup in wakeups:
            wakeup.set()

    def watched(self) -> list[str]:
        """The sessions some stream of this process listens to."""
        with self._lock:
            return list(self._wakeups)

    def notify_all(self) -> None:
        """Wake every stream (after an outage, when some changes may have gone unheard)."""
        with self._lock:
            wakeups = [wakeup for session in self._wakeups.values() for wakeup in session]
        for wakeup in wakeups:
            wakeup.set()

    @contextmanager
    def subscribe(self, session_id: str) -> Iterator[Wakeup]:
        """A flag set by every change of the session, while in the block (in a coroutine)."""
        wakeup = Wakeup()
        with self._lock:
            self._wakeups[session_id].add(wakeup)
        try:
            yield wakeup
        finally:
            with self._lock:
                self._wakeups[session_id].discard(wakeup)
                if not self._wakeups[session_id]:
                    del self._wakeups[session_id]
