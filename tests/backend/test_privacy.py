"""What a session leaves behind: no photo bytes in the database's files once it is deleted
or has expired, no EXIF (GPS) in what is stored, no token, code or position in the logs.

Photos are re-encoded when stored, so the stored JPEG (fetched back from the API) is the
thing to look for: runs of its bytes are searched for in the raw files of the database, as
someone holding the disk would: SQLite's database, write-ahead log and shared-memory
files; PostgreSQL's table files (``base/<database oid>/``, after a CHECKPOINT has written
out every page). Every search is checked first to find the bytes while they are meant to
be there.
"""

from __future__ import annotations

import asyncio
import contextlib
import io
import logging
import time
from collections.abc import Callable, Coroutine
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient
from images import encoded, exif_of
from phones import FakeClock, joined, photos_uploaded
from PIL import ExifTags, Image
from sqlalchemy import Engine

from backend.background import sweep_forever
from backend.main import ERASE_SECONDS
from backend.wiring import Services
from deploy.postgres import PostgresServer
from testbed.client import Phone, numbered, start

# The temple landmarks of the README's example, and where the joiner is in photo 1.
IN_PHOTO1 = [(263, 352), (493, 129), (458, 242), (502, 382), (134, 238), (517, 208)]
IN_PHOTO2 = [(266, 108), (490, 358), (461, 209), (504, 76), (189, 202), (517, 267)]
BUDDY_IN_PHOTO1 = (523, 384)


def answered(starter: Phone, joiner: Phone, photos: tuple[bytes, bytes]) -> None:
    """Both photos uploaded and tapped: the session has an answer (and overlays to draw)."""
    photos_uploaded(starter, joiner, photos)
    starter.tapped(landmarks=numbered(IN_PHOTO1), friend=BUDDY_IN_PHOTO1)
    assert joiner.tapped(landmarks=numbered(IN_PHOTO2))["answer"] is not None


def pictures(client: TestClient, phone: Phone, *, drawn: bool = False) -> list[bytes]:
    """The session's pictures: both stored photos (kept), or both overlays (``drawn``: made
    for each request, never kept)."""
    kind = "overlay" if drawn else "photo"
    return [phone.ok("GET", f"/{kind}/{role}").content for role in ("starter", "joiner")]


def variant(photo: bytes, seed: int) -> bytes:
    """The photo with faint noise of its own: another picture, stored as other bytes (the
    same upload twice would be stored byte for byte the same)."""
    pixels = np.asarray(Image.open(io.BytesIO(photo)).convert("RGB"), dtype=np.int16)
    noise = np.random.default_rng(seed).integers(-3, 4, pixels.shape)
    return encoded(np.clip(pixels + noise, 0, 255).astype(np.uint8), "PNG")


def runs(picture: bytes, count: int = 16, size: int = 64) -> list[bytes]:
    """``count`` runs of ``size`` bytes spread over the middle of a JPEG (its entropy-coded
    data: no two pictures share one)."""
    starts = np.linspace(len(picture) // 8, len(picture) * 7 // 8 - size, count).astype(int)
    return [picture[start : start + size] for start in starts]


class Disk:
    """The raw files of the app's database."""

    def __init__(self, engine: Engine, postgres: PostgresServer | None) -> None:
        self.engine = engine
        self.postgres = postgres

    def files(self) -> list[Path]:
        if self.postgres is None:
            database = Path(str(self.engine.url.database))
            return [Path(f"{database}{suffix}") for suffix in ("", "-wal", "-shm")]
        with self.engine.connect() as connection:
            autocommit = connection.execution_options(isolation_level="AUTOCOMMIT")
            autocommit.exec_driver_sql("CHECKPOINT")  # every changed page out to its file
            oid = autocommit.exec_driver_sql(
                "SELECT oid FROM pg_database WHERE datname = current_database()"
            ).scalar()
        return sorted(path for path in (self.postgres.data / "base" / str(oid)).rglob("*"))

    def read(self) -> bytes:
        return b"".join(path.read_bytes() for path in self.files() if path.is_file())

    def holds(self, picture: bytes) -> int:
        """How many of the picture's runs are in the files."""
        stored = self.read()
        return sum(run in stored for run in runs(picture))


@pytest.fixture
def disk(request: pytest.FixtureRequest, services: Services, database_url: str) -> Disk:
    postgres = request.getfixturevalue("postgres") if "postgresql" in database_url else None
    return Disk(services.database.engine, postgres)


def sweep(services: Services) -> list[str]:
    """One round of the sweeper: expired sessions deleted, deleted bytes erased."""
    gone = services.pairing.sweep()
    services.eraser.erase_deleted()
    return gone


def other_session(client: TestClient, photo: bytes) -> bytes:
    """A second search, still going, with a photo: what erasing must leave alone (its
    stored photo)."""
    return start(client, photo)[0].call("GET", "/photo/starter").content


def test_a_deleted_session_leaves_no_picture_in_the_database_files(
    client: TestClient,
    starter: Phone,
    joiner: Phone,
    temple_photos: tuple[bytes, bytes],
    disk: Disk,
    services: Services,
    database_url: str,
) -> None:
    # A photo replaced by another: the first one's bytes must go too.
    assert starter.upload(variant(temple_photos[0], 1), "first.png").status_code == 200
    replaced = starter.call("GET", "/photo/starter").content
    answered(starter, joiner, temple_photos)
    kept = pictures(client, starter)
    # Another search uploaded after this one's, so that this one's rows are not simply the
    # end of each table (which any VACUUM cuts off).
    other = other_session(client, variant(temple_photos[0], 2))
    crop = starter.call("GET", "/landmarks/joiner/3/crop").content

    for picture in [replaced, *kept, other]:
        assert disk.holds(picture) >= 12  # the search finds what is there
    # Crops and overlays are made from the photo for each request, and never kept.
    for picture in [crop, *pictures(client, starter, drawn=True)]:
        assert disk.holds(picture) == 0

    assert starter.call("DELETE").status_code == 204
    if "sqlite" in database_url:  # within seconds, by the eraser (off the request)
        deadline = time.monotonic() + 10 * ERASE_SECONDS
        while any(disk.holds(p) for p in [replaced, *kept]) and time.monotonic() < deadline:
            time.sleep(0.1)
        for picture in [replaced, *kept]:
            assert disk.holds(picture) == 0
    sweep(services)  # PostgreSQL: by the next sweep
    for picture in [replaced, *kept]:
        assert disk.holds(picture) == 0
    assert disk.holds(other) >= 12


def test_an_expired_session_leaves_no_picture_in_the_database_files(
    client: TestClient,
    starter: Phone,
    joiner: Phone,
    temple_photos: tuple[bytes, bytes],
    disk: Disk,
    services: Services,
    clock: FakeClock,
) -> None:
    answered(starter, joiner, temple_photos)
    kept = pictures(client, joiner)
    clock.advance(3600)
    other = other_session(client, variant(temple_photos[0], 3))  # an hour younger
    for picture in [*kept, other]:
        assert disk.holds(picture) >= 12
    clock.advance(3601)
    assert sweep(services) == [starter.session_id]
    for picture in kept:
        assert disk.holds(picture) == 0
    assert disk.holds(other) >= 12


def photo_with_gps() -> tuple[bytes, bytes]:
    """A JPEG as a phone writes it, EXIF with a GPS position; and that EXIF block."""
    latitude = {"GPSLatitudeRef": "N", "GPSLatitude": (47.0, 22.0, 13.3712)}
    longitude = {"GPSLongitudeRef": "E", "GPSLongitude": (8.0, 32.0, 41.9183)}
    exif = exif_of(None, "BuddyPhone", **latitude, **longitude)
    pixels = np.random.default_rng(7).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    return encoded(pixels, quality=90, exif=exif), exif.tobytes()


# Made once, before any test captures logs (Pillow logs the tags it writes).
GPS_PHOTO, GPS_EXIF = photo_with_gps()


def test_no_exif_or_gps_reaches_the_stored_photo(starter: Phone, joiner: Phone, disk: Disk) -> None:
    upload, exif = GPS_PHOTO, GPS_EXIF
    assert Image.open(io.BytesIO(upload)).getexif().get_ifd(ExifTags.IFD.GPSInfo)  # it has GPS
    assert exif in upload
    assert starter.upload(upload).status_code == 200
    stored = joiner.call("GET", "/photo/starter").content  # as shown
    image = Image.open(io.BytesIO(stored))
    assert image.format == "JPEG"
    assert dict(image.getexif()) == {}
    assert not image.getexif().get_ifd(ExifTags.IFD.GPSInfo)
    assert b"Exif" not in stored
    assert b"BuddyPhone" not in stored
    # Nor is the upload itself kept anywhere: its EXIF block is nowhere in the files.
    assert disk.holds(stored) >= 12
    files = disk.read()
    assert exif not in files
    assert b"BuddyPhone" not in files


# The test's own HTTP client (TestClient is httpx) logs the URLs it requests; the server
# does not use it.
CLIENT_LOGGERS = ("httpx2", "httpcore2")


@pytest.fixture
def logged(caplog: pytest.LogCaptureFixture, monkeypatch: pytest.MonkeyPatch) -> Callable[[], str]:
    """What the server's loggers have logged so far, with the root logger at DEBUG, as a
    handler would write it (tracebacks included)."""
    # SQLAlchemy's statements too (its own logger starts at WARNING): what echo=True shows.
    caplog.set_level(logging.INFO, logger="sqlalchemy.engine")
    caplog.set_level(logging.DEBUG)  # last: it also sets the capturing handler's level
    # Every logger on, also those a logging configuration earlier in the run turned off.
    for logger in logging.root.manager.loggerDict.values():
        if isinstance(logger, logging.Logger):
            monkeypatch.setattr(logger, "disabled", False)
    formatter = logging.Formatter("%(name)s %(levelname)s %(message)s")

    def written() -> str:
        return "\n".join(
            formatter.format(record)
            for record in caplog.records
            if not record.name.startswith(CLIENT_LOGGERS)
        )

    return written


def test_logs_hold_no_token_code_or_position(
    client: TestClient,
    services: Services,
    clock: FakeClock,
    logged: Callable[[], str],
    temple_photos: tuple[bytes, bytes],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    created = client.post("/api/sessions").json()
    code = created["join_code"]
    wrong = f"{(int(code) + 1) % 10**8:08d}"
    assert client.post("/api/sessions/join", json={"code": wrong}).status_code == 404
    starter = Phone(client, created["session_id"], created["token"], "starter")
    joiner = joined(client, code)
    assert starter.upload(GPS_PHOTO).status_code == 200
    photos_uploaded(starter, joiner, temple_photos)
    # Positions nobody else would write: taps with three decimals.
    photo1 = [(x + 0.417, y + 0.583) for x, y in IN_PHOTO1]
    photo2 = [(x + 0.271, y + 0.829) for x, y in IN_PHOTO2]
    starter.tapped(landmarks=numbered(photo1), friend=(523.613, 384.347))
    state = joiner.tapped(landmarks=numbered(photo2))
    position = state["answer"]["in_photo"]["joiner"]["friend"]
    for path in ("/overlay/joiner", "/landmarks/starter/2/crop", "/photo/joiner"):
        answer = client.get(joiner.url(path), params={"token": joiner.token})
        assert answer.status_code == 200
    # An unexpected error on a URL with ?token=: logged with the route, not the URL.
    monkeypatch.setattr(services.pictures, "overlay", lambda *_: 1 / 0)
    failed = client.get(starter.url("/overlay/starter"), params={"token": starter.token})
    assert failed.status_code == 500
    monkeypatch.undo()
    clock.advance(7201)
    sweeper = sweep_forever(services.pairing, services.eraser, 3600)
    asyncio.run(run_for(sweeper, seconds=1))  # logs what it deleted

    written = logged()
    assert "ZeroDivisionError" in written  # records were captured, tracebacks included
    assert "/api/sessions/{session_id}/overlay/{role}" in written
    assert "deleted 1 expired session" in written
    assert "INSERT INTO photos" in written  # the statements, without their parameters
    secrets = [starter.token, joiner.token, code, created["join_url"]]
    positions = [f"{v:.3f}" for point in photo1 + photo2 for v in point]
    positions += ["523.613", "384.347", f"{position[0]:.2f}", f"{position[1]:.2f}"]
    exif = ["13.3712", "41.9183", "BuddyPhone"]
    for secret in secrets + positions + exif:
        assert secret not in written, secret


async def run_for(task: Coroutine[None, None, None], seconds: float) -> None:
    with contextlib.suppress(TimeoutError):
        await asyncio.wait_for(task, seconds)
