"""The engine and its schema: SQLite (WAL, foreign keys, full sync) by default, PostgreSQL
(psycopg 3) for several replicas; the schema is Alembic's migrations, on either."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from alembic import command
from alembic.config import Config
from sqlalchemy import Engine, create_engine, event, inspect, text
from sqlalchemy.engine import URL, make_url
from sqlalchemy.exc import DBAPIError, InterfaceError, OperationalError, SQLAlchemyError
from sqlalchemy.exc import TimeoutError as PoolTimeoutError

MIGRATIONS = Path(__file__).with_name("migrations")
INITIAL_REVISION = "0001"
# Any constant: replicas starting at once take turns to migrate (pg_advisory_xact_lock).
MIGRATION_LOCK = 0x42554459
# How long a SQLite statement waits for the writer's lock before it fails.
SQLITE_BUSY_TIMEOUT_MS = 30_000


class DatabaseUnavailableError(Exception):
    """The database cannot be reached now (down, restarting, every connection busy): a
    503 for requests, a retry for event streams. Not a bug: errors of the SQL itself are
    not this."""


def database_url(url: str) -> URL:
    """``url`` parsed; ``postgresql://`` and ``postgres://`` (as hosting platforms write
    them) mean the psycopg 3 driver, the one installed."""
    if url.startswith("postgres://"):
        url = "postgresql://" + url.removeprefix("postgres://")
    parsed = make_url(url)
    if parsed.drivername == "postgresql":
        parsed = parsed.set(drivername="postgresql+psycopg")
    return parsed


def is_postgresql(url: str) -> bool:
    return database_url(url).get_backend_name() == "postgresql"


def make_engine(url: str) -> Engine:
    """An engine for ``url`` with the schema migrated to the newest revision."""
    engine = connect(url)
    migrate(engine)
    return engine


def connect(url: str) -> Engine:
    """An engine for ``url``, schema untouched.

    SQLite: the file's folder is created; WAL lets readers (event streams) run beside the
    writer; ``synchronous=FULL`` so an acknowledged write survives a crash or power cut;
    foreign keys on, so deleting a session deletes all of it; ``secure_delete`` overwrites
    what is deleted with zeros (a deleted photo's pages are otherwise left as they were in
    the file's free pages). PostgreSQL: each pooled connection is checked before use
    (pre-ping), so the pool recovers by itself after the server restarts; connecting gives
    up after 5 s, so requests fail fast while it is down.

    Either way statement parameters (join codes, taps, photos) are left out of errors and
    logs (``hide_parameters``): an error's message is logged.
    """
    parsed = database_url(url)
    if parsed.get_backend_name() == "sqlite":
        if parsed.database and parsed.database != ":memory:":
            Path(parsed.database).parent.mkdir(parents=True, exist_ok=True)
        engine = create_engine(
            parsed,
            connect_args={"check_same_thread": False, "timeout": 30},
            pool_pre_ping=True,
            hide_parameters=True,
        )
        event.listen(engine, "connect", _sqlite_pragmas)
        return engine
    # 20 connections at most per replica: five replicas fit PostgreSQL's default 100.
    return create_engine(
        parsed,
        pool_pre_ping=True,
        pool_size=10,
        max_overflow=10,
        pool_timeout=10,
        connect_args={"connect_timeout": 5},
        hide_parameters=True,
    )


def migrate(engine: Engine) -> None:
    """``alembic upgrade head``, in one transaction. On PostgreSQL under an advisory lock,
    so replicas starting at once migrate one after the other (the later ones find nothing
    to do). A database made before there were migrations (by ``create_all``: the schema
    of the initial revision) is marked as at that revision first."""
    config = Config()
    config.set_main_option("script_location", str(MIGRATIONS))
    with engine.begin() as connection:
        if connection.dialect.name == "postgresql":
            connection.execute(text("SELECT pg_advisory_xact_lock(:key)"), {"key": MIGRATION_LOCK})
        config.attributes["connection"] = connection
        tables = inspect(connection).get_table_names()
        if "sessions" in tables and "alembic_version" not in tables:
            command.stamp(config, INITIAL_REVISION)
        command.upgrade(config, "head")


def unavailable(error: SQLAlchemyError) -> bool:
    """Whether ``error`` says the database cannot be reached, rather than that a statement
    is wrong: refused or lost connections, a server shutting down, a full pool."""
    if isinstance(error, OperationalError | InterfaceError | PoolTimeoutError):
        return True
    return isinstance(error, DBAPIError) and error.connection_invalidated


def _sqlite_pragmas(connection: Any, _: Any) -> None:
    cursor = connection.cursor()
    cursor.execute("PRAGMA journal_mode=WAL")
    cursor.execute("PRAGMA synchronous=FULL")
    cursor.execute("PRAGMA foreign_keys=ON")
    cursor.execute(f"PRAGMA busy_timeout={SQLITE_BUSY_TIMEOUT_MS}")
    cursor.execute("PRAGMA secure_delete=ON")
    cursor.close()
