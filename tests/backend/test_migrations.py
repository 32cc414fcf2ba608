"""The schema comes from Alembic's migrations, the same on SQLite and PostgreSQL."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from datetime import datetime
from pathlib import Path
from typing import Any

import pytest
from alembic import command
from alembic.autogenerate import compare_metadata
from alembic.config import Config
from alembic.migration import MigrationContext
from alembic.script import ScriptDirectory
from fastapi.testclient import TestClient
from images import store
from phones import TEMPLE_PHOTOS, landmarks, scene
from sqlalchemy import Column, Connection, Engine, String, inspect, text
from sqlalchemy.engine import make_url
from sqlalchemy.types import TypeEngine

from backend.main import create_app
from backend.pairing.tokens import token_hash
from backend.settings import Settings
from backend.storage.database import (
    MIGRATIONS,
    connect,
    database_url,
    make_engine,
    migrate,
)
from backend.storage.tables import Base
from deploy.postgres import PostgresServer

HEAD = ScriptDirectory(str(MIGRATIONS)).get_current_head()
END = datetime(2099, 1, 1)  # when the sessions made here expire


@pytest.fixture(params=["sqlite", "postgresql"])
def empty_database(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[str]:
    """The URL of a database with no tables at all."""
    if request.param == "sqlite":
        yield f"sqlite:///{tmp_path / 'empty.db'}"
        return
    postgres: PostgresServer = request.getfixturevalue("postgres")
    name = postgres.create_database()
    yield postgres.url(name)
    postgres.drop_database(name)


@pytest.fixture
def engine(empty_database: str) -> Iterator[Engine]:
    """The app's engine on the empty database, which it migrates to the newest revision."""
    migrated = make_engine(empty_database)
    yield migrated
    migrated.dispose()


def differences(engine: Engine) -> list[object]:
    """What autogenerate would change to make the database match the models. SQLite does
    not enforce a VARCHAR's length (and changing it there means copying the table), so
    lengths are compared on PostgreSQL only (migration 0005)."""
    with engine.connect() as connection:
        sqlite = connection.dialect.name == "sqlite"
        context = MigrationContext.configure(
            connection, opts={"compare_type": _types_but_lengths if sqlite else True}
        )
        return list(compare_metadata(context, Base.metadata))


def _types_but_lengths(
    context: MigrationContext,
    inspected_column: Column[Any],
    metadata_column: Column[Any],
    inspected_type: TypeEngine[Any],
    metadata_type: TypeEngine[Any],
) -> bool | None:
    """Alembic's type comparison, except that two VARCHARs of any lengths are the same."""
    if isinstance(inspected_type, String) and isinstance(metadata_type, String):
        return type(inspected_type.as_generic()) is not type(metadata_type.as_generic())
    return None  # the default comparison


def alembic_config(connection: Connection) -> Config:
    """Alembic's commands on ``connection``, in its transaction."""
    config = Config()
    config.set_main_option("script_location", str(MIGRATIONS))
    config.attributes["connection"] = connection
    return config


def insert(connection: Connection, table: str, **row: object) -> None:
    """One row of ``table`` of the session 's1' (its ``id``, or its rows' ``session_id``), in
    raw SQL: the tables as of an older migration, not the models."""
    row = {"id" if table == "sessions" else "session_id": "s1"} | row
    values = ", ".join(f":{column}" for column in row)
    connection.execute(text(f"INSERT INTO {table} ({', '.join(row)}) VALUES ({values})"), row)


def revision(engine: Engine) -> str | None:
    with engine.connect() as connection:
        return MigrationContext.configure(connection).get_current_revision()


def test_the_migrated_schema_is_exactly_the_models(engine: Engine) -> None:
    assert revision(engine) == HEAD
    assert differences(engine) == []
    # The comparison does look at indexes, constraints and types: one gone is seen.
    with engine.begin() as connection:
        connection.execute(text("DROP INDEX ix_events_session_id"))
    assert [diff[0] for diff in differences(engine)] == ["add_index"]  # type: ignore[index]


def test_a_downgrade_removes_the_schema_and_an_upgrade_brings_it_back(engine: Engine) -> None:
    with engine.begin() as connection:
        command.downgrade(alembic_config(connection), "base")
    assert inspect(engine).get_table_names() == ["alembic_version"]
    migrate(engine)
    assert differences(engine) == []


def test_eight_digit_codes_keep_every_session_and_clear_six_digit_codes(engine: Engine) -> None:
    """Migration 0005: the sessions and all their rows stay (SQLite's table is not copied,
    which would delete them through the foreign keys); a six-digit code, which the API no
    longer takes, is cleared."""
    with engine.begin() as connection:
        config = alembic_config(connection)
        command.downgrade(config, "0004")
        now = datetime(2026, 11, 21, 20)
        code = {"join_code": "482913", "join_code_expires_at": datetime(2026, 11, 21, 20, 10)}
        end = datetime(2026, 11, 21, 22)
        insert(connection, "sessions", created_at=now, expires_at=end, version=1, **code)
        insert(connection, "participants", role="seeker", token_hash="h1", joined_at=now)
        command.upgrade(config, "0005")
    query = text(
        "SELECT s.join_code, s.join_code_failures, s.join_code_renewals, p.role "
        "FROM sessions s JOIN participants p ON p.session_id = s.id"
    )
    with engine.connect() as connection:
        assert tuple(connection.execute(query).one()) == (None, 0, 0, "seeker")


# Stored answers of a shape their migration changed: warnings as bare sentences (0009), a
# refusal as a code and a sentence naming photo 1 (0010).
OLD_ANSWERS = {
    "0009": {"answer": {"in_photo": {"joiner": {"warnings": ["The position is uncertain."]}}}},
    "0010": {
        "error": {"code": "collinear_landmarks", "message": "All landmarks in photo 1 lie..."},
        "first": "starter",
    },
}


@pytest.mark.parametrize("revision", OLD_ANSWERS)
def test_answers_of_an_old_shape_are_cleared(engine: Engine, revision: str) -> None:
    """Migrations 0009 and 0010: a stored answer of the shape before is cleared (the state
    answers again); the session stays."""
    answer = OLD_ANSWERS[revision]
    with engine.begin() as connection:
        config = alembic_config(connection)
        command.downgrade(config, f"{int(revision) - 1:04d}")
        times = {"created_at": datetime(2026, 11, 26), "expires_at": END}
        stored = {"version": 7, "answer": json.dumps(answer), "answer_version": 7}
        insert(connection, "sessions", **times, **stored)
        command.upgrade(config, revision)
    with engine.connect() as connection:
        row = connection.execute(text("SELECT version, answer, answer_version FROM sessions"))
        assert tuple(row.one()) == (7, None, None)


def test_a_live_search_of_seeker_and_buddy_carries_on_as_starter_and_joiner(
    empty_database: str, engine: Engine, tmp_path: Path
) -> None:
    """Migration 0006: roles, taps and events in the friends' words, each tap's old
    coordinates kept; the stored answer (of the old shape) is cleared, and the next read of
    the state answers again."""
    s = scene(6, seed=3)
    seeker = {"landmarks": landmarks(s.landmarks1), "epipole1": list(s.epipole1)}
    old = {"seeker": seeker, "buddy": {"landmarks": landmarks(s.landmarks2), "epipole2": None}}
    stored = dict(zip(("seeker", "buddy"), map(store, TEMPLE_PHOTOS), strict=True))
    with engine.begin() as connection:
        command.downgrade(alembic_config(connection), "0005")
        now = datetime(2026, 11, 25, 8)
        result = {"result": '{"result": {}}', "result_version": 7}
        insert(connection, "sessions", created_at=now, expires_at=END, version=7, **result)
        for role in ("seeker", "buddy"):
            person = {"role": role, "token_hash": token_hash(role)}
            insert(connection, "participants", **person, joined_at=now, taps=json.dumps(old[role]))
            photo = stored[role]
            sizes = {"width": photo.width, "height": photo.height, "scale": 1.0}
            insert(connection, "photos", role=role, data=photo.data, **sizes, uploaded_at=now)
        old_events = [("result", {"version": 7}), ("taps", {"role": "buddy", "version": 7})]
        for kind, data in old_events:
            insert(connection, "events", type=kind, data=json.dumps(data), created_at=now)
    migrate(engine)
    assert differences(engine) == []
    with engine.connect() as connection:
        events = connection.execute(text("SELECT type, data FROM events ORDER BY id")).all()
        assert [tuple(e) for e in events] == [
            ("answer", '{"version": 7}'),
            ("taps", '{"role": "joiner", "version": 7}'),
        ]
        assert connection.scalar(text("SELECT answer FROM sessions")) is None
    settings = Settings(database_url=empty_database)
    with TestClient(create_app(settings)) as client:
        state = client.get("/api/sessions/s1", headers={"Authorization": "Bearer seeker"})
        assert state.status_code == 200, state.text
        body = state.json()
        assert body["you"] == "starter"
        assert body["taps"]["starter"]["friend"]["x"] == pytest.approx(s.epipole1[0])
        assert body["taps"]["joiner"]["landmarks"][2]["y"] == pytest.approx(s.landmarks2[2][1])
        assert body["answer"]["in_photo"]["joiner"]["how"] == "solved"  # answered again


def test_a_database_from_before_migrations_is_kept_and_adopted(empty_database: str) -> None:
    """``make run`` created its SQLite file with ``create_all`` before there were
    migrations: its sessions stay, and it is marked as migrated."""
    engine = connect(empty_database)
    # The tables of those days: all but those and the columns added by later revisions,
    # and the overlays that a later revision dropped.
    Base.metadata.create_all(
        engine, tables=[t for t in Base.metadata.sorted_tables if t.name != "join_failures"]
    )
    blob = "BLOB" if "sqlite" in empty_database else "BYTEA"
    with engine.begin() as connection:
        for added in ("join_code_failures", "join_code_renewals"):
            connection.execute(text(f"ALTER TABLE sessions DROP COLUMN {added}"))
        later = ("lens_focal_35mm", "lens_uncertainty", "lens_told_by", "version", "gravity")
        for added in (*later, "heading", "heading_sigma_deg"):
            connection.execute(text(f"ALTER TABLE photos DROP COLUMN {added}"))
        for old, new in (("result", "answer"), ("result_version", "answer_version")):
            connection.execute(text(f"ALTER TABLE sessions RENAME COLUMN {new} TO {old}"))
        connection.execute(
            text(
                "CREATE TABLE overlays (session_id VARCHAR(32) NOT NULL REFERENCES sessions(id) "
                "ON DELETE CASCADE, role VARCHAR(6) NOT NULL, format VARCHAR(4) NOT NULL, "
                f"version INTEGER NOT NULL, data {blob} NOT NULL, "
                "PRIMARY KEY (session_id, role, format))"
            )
        )
        now = datetime(2026, 11, 21, 20)
        insert(connection, "sessions", created_at=now, expires_at=END, version=1)
    engine.dispose()
    engine = make_engine(empty_database)
    try:
        assert revision(engine) == HEAD
        assert differences(engine) == []
        with engine.connect() as connection:
            assert connection.scalar(text("SELECT id FROM sessions")) == "s1"
    finally:
        engine.dispose()


def test_replicas_starting_at_once_migrate_one_after_the_other(empty_database: str) -> None:
    """Without the lock (PostgreSQL's advisory lock, the lock file beside a SQLite file),
    two CREATE TABLEs race and one replica or worker process fails to start."""
    url = empty_database
    failures: list[BaseException] = []
    engines: list[Engine] = []
    start = threading.Barrier(4)

    def replica() -> None:
        start.wait(timeout=30)
        try:
            engines.append(make_engine(url))
        except Exception as error:
            failures.append(error)

    threads = [threading.Thread(target=replica) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=60)
    try:
        assert failures == []
        assert len(engines) == 4
        assert revision(engines[0]) == HEAD
        assert differences(engines[0]) == []
    finally:
        for engine in engines:
            engine.dispose()


def test_plain_postgresql_urls_mean_psycopg() -> None:
    """As hosting platforms write them: postgres:// and postgresql:// without a driver."""
    for url in ("postgres://u:p@db:5432/buddy", "postgresql://u:p@db:5432/buddy"):
        # psycopg's driver, every other part as written
        assert database_url(url) == make_url("postgresql+psycopg://u:p@db:5432/buddy")
    assert database_url("sqlite:///var/buddy.db").drivername == "sqlite"


def test_postgresql_keeps_photo_bytes_uncompressed(fresh_postgres_url: str) -> None:
    """Migration 0007: no compression is tried on the photos' JPEG bytes (which do not
    compress), neither at an upload nor when VACUUM FULL copies the photos kept."""
    engine = connect(fresh_postgres_url)
    data = "attrelid = 'photos'::regclass AND attname = 'data'"  # the photos' bytes
    try:
        with engine.connect() as connection:
            query = text(f"SELECT attstorage FROM pg_attribute WHERE {data}")
            storage = connection.execute(query).scalar_one()
        assert storage == "e"  # EXTERNAL: out of line, never compressed
    finally:
        engine.dispose()
