"""The background task that deletes expired sessions (and with them their photos)."""

from __future__ import annotations

import asyncio
import logging

import anyio

from backend.sessions.service import SessionService
from backend.storage.database import DatabaseUnavailableError

log = logging.getLogger(__name__)


async def sweep_forever(service: SessionService, interval_seconds: float) -> None:
    """Every ``interval_seconds``: delete what has expired. Never dies of an error."""
    while True:
        try:
            gone = await anyio.to_thread.run_sync(service.sweep)
            if gone:
                log.info("deleted %d expired session(s)", len(gone))
        except DatabaseUnavailableError as error:
            log.warning("sweeping expired sessions waits for the database: %s", error)
        except Exception:
            log.exception("sweeping expired sessions failed; trying again later")
        await asyncio.sleep(interval_seconds)
