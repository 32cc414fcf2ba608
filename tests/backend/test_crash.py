"""Crash safety: the server killed with ``kill -9`` in the middle of uploads and tap changes
loses no acknowledged write and leaves nothing half-written, on SQLite and on PostgreSQL.

A real uvicorn process serves four searches; one thread per phone (eight) sends photos and
tap sets one after the other, as a phone does. At a random moment the process is killed
(SIGKILL: no shutdown, no rollback by the app), a new one is started on the same database
(on PostgreSQL the database server stays up: only the app dies), and then:

- every write that was answered 2xx is there: each phone's photo is, byte for byte, the
  stored form of the last photo it had acknowledged, or of the one in flight at the kill;
  its taps are exactly the last acknowledged set, or the set in flight (never a mix); the
  session's version is at least the last one a phone was told;
- nothing is half-written: each stored photo decodes to the size its row says; every tap
  set is whole; each stored change has its version and its one event (versions 3, 4, ... in
  the order of the event ids, as many events of a phone as changes of it are stored);
  SQLite's ``PRAGMA integrity_check`` says ok on the file as the killed process left it;
- the new process started on the crashed database (it answers /healthz) and serves it.

Three kill points in a row, each followed by a restart.
"""

from __future__ import annotations

import io
import json
import os
import signal
import sqlite3
import threading
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import httpx2
import numpy as np
from images import encoded, store
from phones import stored_photo
from PIL import Image
from sqlalchemy import text

from backend.storage.database import connect
from backend.taps.schemas import Taps
from deploy.replica import Server, serve
from testbed.client import Phone, live, numbered, pair

SEARCHES = 4
KILLS = 3
# The kill comes at a random moment after every phone has had, on average, this many
# changes acknowledged (waiting for a count, not a time, keeps a slow machine from
# killing before the traffic is under way), and at most this long after it.
ACKNOWLEDGED_BEFORE_KILL = 2
KILL_DELAY_SECONDS = (0.0, 1.0)
TRAFFIC_START_SECONDS = 60.0
LANDMARKS = 6
# Photos of different sizes (each recognisable from its stored size), all larger than the
# area taps are drawn in, so every tap set fits every photo.
PHOTO_SIZES = [(240 + 16 * k, 180 + 8 * k) for k in range(6)]
TAP_AREA = (240, 180)


def photo(index: int) -> bytes:
    width, height = PHOTO_SIZES[index]
    pixels = np.random.default_rng(index).integers(0, 256, (height, width, 3), dtype=np.uint8)
    return encoded(pixels, quality=85)


PHOTOS = [photo(index) for index in range(len(PHOTO_SIZES))]
# What the server stores for each (the same code, deterministic, and none of them near its
# limits): recognised byte for byte.
STORED = [store(data) for data in PHOTOS]


@dataclass(frozen=True)
class Change:
    """One request a phone sends: a new photo (which clears its taps) or a new tap set."""

    photo: int | None = None
    taps: dict[str, Any] | None = None

    def applied_to(self, state: PhoneState) -> PhoneState:
        if self.photo is not None:
            return PhoneState(self.photo, None)
        return PhoneState(state.photo, Taps.model_validate(self.taps).model_dump(mode="json"))


@dataclass(frozen=True)
class PhoneState:
    """What the server should hold of one phone: its photo (an index in PHOTOS) and taps
    (as the state reports them)."""

    photo: int | None
    taps: dict[str, Any] | None


@dataclass
class Writer:
    """One phone's writes: what it sent, and what it was told."""

    phone: Phone  # who it is (its client replaced by one of the server of the moment)
    known: PhoneState = PhoneState(None, None)  # as of the last acknowledged change
    in_flight: Change | None = None  # sent, unanswered when the server died
    stored: int = 0  # changes known to be stored: acknowledged, or in flight and found
    acknowledged: int = 0  # changes answered 2xx in this round
    acknowledged_version: int = 0  # the highest version an answer told this phone

    def on(self, http: httpx2.Client) -> Phone:
        """The phone, calling through ``http``."""
        return replace(self.phone, client=http)


@dataclass
class Traffic:
    """Every phone's thread sending changes, one after the other, until the server is gone."""

    base: str
    phones: list[Writer]
    rng: np.random.Generator
    failures: list[str] = field(default_factory=list)

    def start(self) -> list[threading.Thread]:
        seeds = self.rng.integers(0, 2**32, len(self.phones))
        for phone in self.phones:
            phone.acknowledged = 0
        threads = [
            threading.Thread(target=self._send, args=(phone, int(seed)), daemon=True)
            for phone, seed in zip(self.phones, seeds, strict=True)
        ]
        for thread in threads:
            thread.start()
        return threads

    def _send(self, phone: Writer, seed: int) -> None:
        rng = np.random.default_rng(seed)
        with httpx2.Client(base_url=self.base, timeout=30) as http:
            sender = phone.on(http)
            while True:
                change = phone.in_flight = self._change(phone, rng)
                try:
                    if change.photo is not None:
                        answer = sender.upload(PHOTOS[change.photo])
                    else:
                        answer = sender.tap(**(change.taps or {}))
                except httpx2.TransportError:
                    return  # the server is gone: this change may or may not have been stored
                if answer.status_code != 200:
                    self.failures.append(f"{sender.role} of {sender.session_id}: {answer.text}")
                    return
                phone.known, phone.in_flight = change.applied_to(phone.known), None
                phone.stored += 1
                phone.acknowledged += 1
                if change.taps is not None:
                    version = answer.json()["version"]
                    phone.acknowledged_version = max(phone.acknowledged_version, version)

    @staticmethod
    def _change(phone: Writer, rng: np.random.Generator) -> Change:
        """A new photo (never the one it has) or a new tap set: every change shows."""
        if phone.known.photo is None or rng.random() < 0.3:
            others = [n for n in range(len(PHOTOS)) if n != phone.known.photo]
            return Change(photo=int(rng.choice(others)))
        points = rng.uniform((0, 0), TAP_AREA, (LANDMARKS, 2)).round(2)
        taps: dict[str, Any] = {"landmarks": numbered(points.tolist())}
        if phone.phone.role == "starter":
            x, y = rng.uniform((0, 0), TAP_AREA).round(2).tolist()
            taps["friend"] = {"x": x, "y": y}
        return Change(taps=taps)


def kill_mid_traffic(server: Server, phones: list[Writer], rng: np.random.Generator) -> None:
    """Traffic from every phone, then SIGKILL at a random moment in it."""
    traffic = Traffic(server.base_url, phones, rng)
    threads = traffic.start()
    started = time.monotonic() + TRAFFIC_START_SECONDS
    while sum(phone.acknowledged for phone in phones) < ACKNOWLEDGED_BEFORE_KILL * len(phones):
        assert time.monotonic() < started, "the traffic did not get under way"
        assert not traffic.failures, traffic.failures
        time.sleep(0.02)
    time.sleep(float(rng.uniform(*KILL_DELAY_SECONDS)))
    os.kill(server.pid, signal.SIGKILL)
    for thread in threads:
        thread.join(timeout=30)
        assert not thread.is_alive()
    assert not traffic.failures, traffic.failures
    acknowledged = sum(phone.acknowledged for phone in phones)
    assert acknowledged >= ACKNOWLEDGED_BEFORE_KILL * len(phones), acknowledged
    assert any(phone.in_flight for phone in phones), "nothing was in flight at the kill"


def check_acknowledged_writes(server: Server, phones: list[Writer]) -> None:
    """Each phone's photo and taps are what it last had acknowledged, or what it had in
    flight (then that counts as stored from now on)."""
    for phone in phones:
        role, session_id = phone.phone.role, phone.phone.session_id
        with live(server.base_url) as http:
            reader = phone.on(http)
            body, stored = reader.state(), reader.ok("GET", f"/photo/{role}")
        session = [p.acknowledged_version for p in phones if p.phone.session_id == session_id]
        assert body["version"] >= max(session)
        found = PhoneState([p.data for p in STORED].index(stored.content), body["taps"][role])
        allowed = [phone.known]
        if phone.in_flight is not None:
            allowed.append(phone.in_flight.applied_to(phone.known))
        assert found in allowed, (role, session_id, found, allowed)
        assert found.photo is not None
        width, height = PHOTO_SIZES[found.photo]
        assert body["photos"][role] == stored_photo(width, height)
        if found != phone.known:
            phone.stored += 1
        phone.known, phone.in_flight = found, None


def check_database_intact(database_url: str) -> None:
    """SQLite: the file the killed process left is consistent, before anyone recovers it."""
    if database_url.startswith("sqlite"):
        path = database_url.removeprefix("sqlite:///")
        with sqlite3.connect(path) as db:
            assert db.execute("PRAGMA integrity_check").fetchall() == [("ok",)]
            assert db.execute("PRAGMA foreign_key_check").fetchall() == []


def check_nothing_half_written(database_url: str, phones: list[Writer]) -> None:
    """Every row is whole, and every stored change has its version and its event."""
    engine = connect(database_url)
    try:
        with engine.connect() as db:
            for row in db.execute(text("SELECT data, width, height FROM photos")):
                with Image.open(io.BytesIO(row.data)) as image:
                    image.load()
                    assert image.size == (row.width, row.height)
            for row in db.execute(text("SELECT taps FROM participants WHERE taps IS NOT NULL")):
                Taps.model_validate_json(row.taps)
            sessions = db.execute(text("SELECT id, version, answer, answer_version FROM sessions"))
            for session in sessions:
                events = db.execute(
                    text("SELECT type, data FROM events WHERE session_id = :id ORDER BY id"),
                    {"id": session.id},
                ).all()
                changes = [json.loads(e.data) for e in events if e.type in ("photo", "taps")]
                # One event per version bump (joining made 2; then each photo or tap set).
                assert [c["version"] for c in changes] == list(range(3, session.version + 1))
                for phone in phones:
                    if phone.phone.session_id == session.id:
                        events_of_phone = sum(c["role"] == phone.phone.role for c in changes)
                        assert events_of_phone == phone.stored, "a change without its event"
                answered = [json.loads(e.data)["version"] for e in events if e.type == "answer"]
                assert answered == sorted(answered)
                if session.answer_version is not None:
                    assert session.answer_version in answered
                    json.loads(session.answer)
    finally:
        engine.dispose()


def test_kill_9_mid_traffic_loses_no_acknowledged_write(
    tmp_path: Path, database_url: str, rng: np.random.Generator
) -> None:
    environment = {"BUDDY_DATABASE_URL": database_url}
    phones: list[Writer] = []
    for process in range(KILLS + 1):
        folder = tmp_path / f"process{process}"
        folder.mkdir()
        with serve(folder, environment) as server:  # on the database the last one crashed on
            if phones:
                check_acknowledged_writes(server, phones)
                check_nothing_half_written(database_url, phones)
            else:
                with live(server.base_url) as http:
                    phones = [Writer(phone) for _ in range(SEARCHES) for phone in pair(http)]
            if process < KILLS:
                kill_mid_traffic(server, phones, rng)
        check_database_intact(database_url)
