"""One erase for the whole cluster per interval (PostgreSQL).

Erasing deleted rows' bytes from PostgreSQL's files is ``VACUUM FULL``, which locks each
table while it copies every row kept: every request touching it waits. When each replica
erased after its own deletions, N replicas made N such stalls per interval; in the load
benchmark (benchmarks/load.py) the two replicas' erases were what kept p99 above 1 s.

So erasing takes a turn: the replica that erases holds a PostgreSQL advisory lock, on a
connection of its own, for one interval from then. Meanwhile another replica's try fails
and its deletions wait, to be erased in the next turn: still within an interval of their
deletion (plus a sweep), as before. A replica that dies or loses its connection frees the
turn with it (the lock belongs to the connection).
"""

from __future__ import annotations

import math
import time
from contextlib import suppress

from sqlalchemy import Connection, Engine, text
from sqlalchemy.exc import SQLAlchemyError

# The advisory lock's key: any number no other lock of this database uses ("erase").
ERASE_TURN_KEY = 0x6572617365
_TRY = text("SELECT pg_try_advisory_lock(:key)").bindparams(key=ERASE_TURN_KEY)
_UNLOCK = text("SELECT pg_advisory_unlock(:key)").bindparams(key=ERASE_TURN_KEY)


class EraseTurn:
    """This replica's turn to erase, taken for ``interval_seconds`` at a time."""

    def __init__(self, engine: Engine, interval_seconds: float) -> None:
        self._engine = engine
        self._interval = interval_seconds
        self._held: Connection | None = None  # the connection holding the lock
        self._since = -math.inf  # time.monotonic() when the turn was taken

    def end_if_over(self) -> None:
        """Give the turn back once its interval has passed."""
        if self._held is not None and time.monotonic() - self._since >= self._interval:
            held, self._held = self._held, None
            # Unlocked, or gone with its connection (which frees the lock as well).
            with suppress(SQLAlchemyError):
                held.execute(_UNLOCK)
                held.commit()
            held.close()

    def take(self) -> bool:
        """Whether this replica may erase now: no replica, this one included, has erased
        within the interval. If so, the turn is this replica's for an interval."""
        if self._held is not None:
            return False
        connection = self._engine.connect()
        try:
            taken = bool(connection.scalar(_TRY))
            connection.commit()  # the lock outlives the transaction; no snapshot is kept
        except BaseException:
            connection.close()
            raise
        if not taken:
            connection.close()
            return False
        self._held, self._since = connection, time.monotonic()
        return True
