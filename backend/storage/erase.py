"""Erasing what deleted rows leave in the database's files (photos, taps, answers).

A deletion marks the eraser pending; the background eraser (:mod:`backend.background`)
calls :meth:`Eraser.erase_deleted` within seconds, off the request, so that **Delete now**
answers at once and deletions close together are erased together.
"""

from __future__ import annotations

import threading

from sqlalchemy.exc import DBAPIError

from .database import SQLITE_BUSY_TIMEOUT_MS, Database, translated
from .erasing import EraseTurn

# What VACUUM FULL rewrites: everything of a session, and the failed joins' addresses.
_ERASED_TABLES = ("sessions", "participants", "photos", "events", "join_failures")
_CHECKPOINT_WAIT_MS = 1000
# VACUUM FULL waits this long for each table's lock (queueing requests behind it), then gives
# up until the next sweep.
_ERASE_LOCK_TIMEOUT = "5s"


class Eraser:
    def __init__(self, database: Database, interval_seconds: float = 0.0) -> None:
        self.database = database
        self._pending = False
        # The sweeper and the eraser call from threads of their own: one erase at a time,
        # so that a call made while another erases returns once those bytes are gone.
        self._erasing = threading.Lock()
        # PostgreSQL: one VACUUM FULL per erase interval for all replicas (erasing.py).
        self._erase_turn = EraseTurn(database.engine, interval_seconds)

    def deleted(self) -> None:
        """Something was deleted: its bytes are for :meth:`erase_deleted` to erase."""
        self._pending = True

    def erase_deleted(self) -> bool:
        """Erase from the database's files the bytes of rows deleted since the last call:
        True when nothing is left to erase, False when it must be tried again (the sweeper
        does, at its next round).

        SQLite overwrites deleted content with zeros as it deletes (``secure_delete``), but
        its write-ahead log still holds every page as it was written, photos included: the
        log is checkpointed into the database and truncated to nothing. That waits 1 s at
        most for readers on an older snapshot, and otherwise fails, to be tried again.

        PostgreSQL leaves a deleted row's bytes in its table's files, and VACUUM only marks
        that space free: VACUUM FULL copies each table without them into a new file and
        deletes the old one. It locks each table while copying it (requests touching it
        wait: the load benchmark reports how long), so it runs at most once per
        ``interval_seconds`` for all replicas together (the one that erases takes the
        turn: erasing.py), after deletions only, giving up a table's lock after 5 s.
        PostgreSQL's own write-ahead log (``pg_wal``, and any archive or backup of it)
        keeps the bytes until it is recycled: outside the app's reach.
        """
        with self._erasing:
            return self._erase()

    def _erase(self) -> bool:
        postgresql = self.database.postgresql
        if postgresql:
            with translated():
                self._erase_turn.end_if_over()
        if not self._pending:
            return True
        if postgresql:
            with translated():
                if not self._erase_turn.take():  # erased within the interval, here or not
                    return False
        self._pending = False  # a deletion from here on sets it again
        try:
            done = self._vacuum_full() if postgresql else self._checkpoint()
        except BaseException:
            self._pending = True
            raise
        if not done:
            self._pending = True
        return done

    def _checkpoint(self) -> bool:
        # As a writer: the checkpoint blocks writers anyway, who wait in line meanwhile.
        with self.database.writing(), translated(), self.database.engine.connect() as connection:
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
        with translated(), self.database.engine.connect() as connection:
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
