"""The background tasks: deleting expired sessions (and with them their photos), erasing
what deletions leave in the database's files, keeping the phones that listen here online,
and (SQLite) watching for other processes' changes."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable

import anyio

from backend.eventstream.stream import EventStreams
from backend.pairing.service import PairingService
from backend.storage.database import DatabaseUnavailableError
from backend.storage.erase import Eraser

log = logging.getLogger(__name__)


async def sweep_forever(pairing: PairingService, eraser: Eraser, interval_seconds: float) -> None:
    """Every ``interval_seconds``: delete what has expired, and erase what deletions left
    in the database's files. Never dies of an error."""

    def sweep() -> None:
        if gone := pairing.sweep():
            log.info("deleted %d expired session(s)", len(gone))
        eraser.erase_deleted()

    await _forever(sweep, interval_seconds, "sweeping expired sessions")


async def keep_online_forever(streams: EventStreams, interval_seconds: float) -> None:
    """Every ``interval_seconds``: the phones listening here are seen (one write)."""
    await _forever(streams.keep_online, interval_seconds, "marking listening phones online")


async def erase_forever(eraser: Eraser, interval_seconds: float) -> None:
    """Every ``interval_seconds``: erase what deletions left in the database's files (at
    once on SQLite; on PostgreSQL at most every ``erase_interval_seconds``)."""

    def erase() -> None:
        eraser.erase_deleted()

    await _forever(erase, interval_seconds, "erasing deleted rows")


async def watch_events_forever(streams: EventStreams, interval_seconds: float) -> None:
    """Every ``interval_seconds``: wake the streams of sessions other processes changed
    (several worker processes on one SQLite file, which have no LISTEN/NOTIFY)."""
    after: int | None = None

    def watch() -> None:
        nonlocal after
        after = streams.watch(after)

    await _forever(watch, interval_seconds, "watching for other processes' changes")


async def _forever(work: Callable[[], None], interval_seconds: float, what: str) -> None:
    """``work`` in a worker thread, then a pause, for ever; an error is logged, not fatal."""
    while True:
        try:
            await anyio.to_thread.run_sync(work)
        except DatabaseUnavailableError as error:
            log.warning("%s waits for the database: %s", what, error)
        except Exception:
            log.exception("%s failed; trying again later", what)
        await asyncio.sleep(interval_seconds)
