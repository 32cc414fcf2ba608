"""PostgreSQL: one erase (VACUUM FULL, which locks each table while it copies it) per erase
interval for all replicas together, not one per replica (backend/storage/erasing.py); and
within a replica, one erase at a time (backend/storage/erase.py)."""

from __future__ import annotations

import threading
import time
from datetime import timedelta

import pytest
from sqlalchemy import text

from backend.clock import utc_now
from backend.pairing.repository import Pairings
from backend.storage.database import Database, connect
from backend.storage.erase import Eraser

INTERVAL_SECONDS = 1.0


class Replica:
    """What one replica erases with: its database, its eraser, its sessions."""

    def __init__(self, url: str) -> None:
        self.database = Database(connect(url))
        self.eraser = Eraser(self.database, INTERVAL_SECONDS)
        self.pairings = Pairings(self.database, self.eraser)
        self.erase_deleted = self.eraser.erase_deleted


def a_deletion(replica: Replica, number: int) -> None:
    """A session made and deleted through ``replica``: bytes for it to erase."""
    now = utc_now()
    later = now + timedelta(hours=1)
    assert replica.pairings.create(
        f"erase{number:027d}",
        starter_token_hash=f"hash{number}",
        join_code=f"{number:08d}",
        now=now,
        expires_at=later,
        join_code_expires_at=later,
    )
    assert replica.pairings.delete(f"erase{number:027d}")


def table_file(replica: Replica) -> int:
    """The sessions table's file: each VACUUM FULL writes a new one."""
    query = text("SELECT relfilenode FROM pg_class WHERE relname = 'sessions'")
    with replica.database.engine.connect() as connection:
        return int(connection.scalar(query))


def test_replicas_take_turns_to_erase_once_per_interval(fresh_postgres_url: str) -> None:
    first, second = Replica(fresh_postgres_url), Replica(fresh_postgres_url)
    try:
        a_deletion(first, 1)
        a_deletion(second, 2)
        before = table_file(first)
        assert first.erase_deleted()  # it erases, and the turn is its own for the interval
        erased = table_file(first)
        assert erased != before
        assert not second.erase_deleted()  # not its turn: its deletion waits
        a_deletion(first, 3)
        assert not first.erase_deleted()  # once per interval, for it as well
        assert table_file(first) == erased

        time.sleep(INTERVAL_SECONDS)
        assert not second.erase_deleted()  # the first replica has not given the turn back yet
        assert first.erase_deleted()  # it does now, then takes it again for its own deletion
        assert table_file(first) != erased
        erased = table_file(first)

        time.sleep(INTERVAL_SECONDS)
        assert first.erase_deleted()  # the turn given back, nothing of its own to erase
        assert table_file(first) == erased
        assert second.erase_deleted()  # the second replica's turn at last
        assert table_file(first) != erased
    finally:
        for replica in (first, second):
            replica.database.engine.dispose()


def test_a_call_while_another_erases_returns_once_the_bytes_are_gone(
    database_url: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The sweeper and the eraser run in threads of their own: the one that finds the
    other erasing does not say "nothing left" while the bytes are still there."""
    replica = Replica(database_url)
    erase = Eraser._vacuum_full if replica.database.postgresql else Eraser._checkpoint
    started, finish = threading.Event(), threading.Event()
    finished: list[str] = []

    def held(eraser: Eraser) -> bool:
        started.set()
        assert finish.wait(10)
        done = erase(eraser)
        finished.append("first")
        return done

    monkeypatch.setattr(Eraser, erase.__name__, held)
    try:
        a_deletion(replica, 4)
        first = threading.Thread(target=replica.erase_deleted)
        first.start()
        assert started.wait(10)
        threading.Timer(0.3, finish.set).start()
        assert replica.erase_deleted()  # nothing left: the first call erased it meanwhile
        finished.append("second")
        first.join(10)
        assert finished == ["first", "second"]
    finally:
        finish.set()
        replica.database.engine.dispose()
