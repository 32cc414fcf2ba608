"""The engine and its schema: SQLite (WAL, foreign keys, full sync) by default, PostgreSQL
(psycopg 3) for several replicas; the schema is Alembic's migrations, on either."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import AbstractContextManager, contextmanager, nullcontext
from pathlib import Path
from typing import IO, Any

import portalocker
from alembic import command
from alembic.config import Config
from sqlalchemy import Connection, Engine, create_engine, event, inspect, text
from sqlalchemy.engine import URL, make_url
from sqlalchemy.exc import DBAPIError, InterfaceError, OperationalError, SQLAlchemyError
from sqlalchemy.exc import TimeoutError as PoolTimeoutError
from sqlalchemy.orm import Session, sessionmaker

from backend import timing

MIGRATIONS = Path(__file__).with_name("migrations")
INITIAL_REVISION = "0001"
# Any constant: replicas starting at once take turns to migrate (pg_advisory_xact_lock).
MIGRATION_LOCK = 0x42554459
# How long a SQLite statement waits for the writer's lock before it fails.
SQLITE_BUSY_TIMEOUT_MS = 30_000
SQLITE_CONNECTIONS = 40


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
    the file's free pages). PostgreSQL: connecting gives up after 5 s, so requests fail fast
    while it is down; after it restarts, the first query that finds its connection gone
    fails (503, which the phones retry) and has the whole pool replaced, so the pool
    recovers by itself. No check before each use (pre-ping): that cost a round trip to
    the server before every query of every request.

    Either way statement parameters (join codes, taps, photos) are left out of errors and
    logs (``hide_parameters``): an error's message is logged.
    """
    parsed = database_url(url)
    if parsed.get_backend_name() == "sqlite":
        pool: dict[str, Any] = {}
        if parsed.database and parsed.database != ":memory:":
            Path(parsed.database).parent.mkdir(parents=True, exist_ok=True)
            # A file never drops a connection: no pre-ping (a query per checkout). As many
            # connections as worker threads (anyio's default 40), so none waits for one.
            pool = {"pool_size": SQLITE_CONNECTIONS, "max_overflow": 0}
        engine = create_engine(
            parsed,
            connect_args={"check_same_thread": False, "timeout": 30},
            hide_parameters=True,
            **pool,
        )
        event.listen(engine, "connect", _sqlite_pragmas)
        return _tallied(engine)
    # 20 connections per replica: five replicas fit PostgreSQL's default 100. A fixed pool:
    # overflow connections (opened past the pool's size, closed when given back) made
    # PostgreSQL start a backend and check a password for each, 8.5 times per search under
    # load (benchmarks/load.py, 200 searches at once).
    return _tallied(
        create_engine(
            parsed,
            pool_size=20,
            max_overflow=0,
            pool_timeout=10,
            connect_args={"connect_timeout": 5, **PREPARED},
            hide_parameters=True,
        )
    )


def _tallied(engine: Engine) -> Engine:
    """``engine``, each of whose statements adds its time (sent, run, answer read) to the
    request's ``Server-Timing`` (:mod:`backend.timing`)."""

    def started(connection: Connection, *_: object) -> None:
        connection.info["statement_started"] = time.perf_counter()

    def ended(connection: Connection, *_: object) -> None:
        began = connection.info.pop("statement_started", None)
        if began is not None:
            timing.add(timing.DATABASE, time.perf_counter() - began)

    event.listen(engine, "before_cursor_execute", started)
    event.listen(engine, "after_cursor_execute", ended)
    return engine


# Every statement prepared on its first run on a connection (psycopg's default waits for
# the fifth) and planned once for all its parameters: the app's statements are a few dozen
# lookups by key, each run thousands of times, and parsing and planning them afresh was a
# third of PostgreSQL's CPU under load (docs/load-benchmark.md).
PREPARED: dict[str, Any] = {
    "prepare_threshold": 0,
    "options": "-c plan_cache_mode=force_generic_plan",
}


def migrate(engine: Engine) -> None:
    """``alembic upgrade head``, in one transaction. Under a lock (PostgreSQL: advisory; a
    SQLite file: a lock file beside it), so replicas or worker processes starting at once
    migrate one after the other (the later ones find nothing to do). A database made
    before there were migrations (by ``create_all``: the schema of the initial revision) is
    marked as at that revision first."""
    config = Config()
    config.set_main_option("script_location", str(MIGRATIONS))
    with _one_at_a_time(engine), engine.begin() as connection:
        if connection.dialect.name == "postgresql":
            connection.execute(text("SELECT pg_advisory_xact_lock(:key)"), {"key": MIGRATION_LOCK})
        config.attributes["connection"] = connection
        tables = inspect(connection).get_table_names()
        if "sessions" in tables and "alembic_version" not in tables:
            command.stamp(config, INITIAL_REVISION)
        command.upgrade(config, "head")


@contextmanager
def _one_at_a_time(engine: Engine) -> Iterator[None]:
    """On a SQLite file, worker processes starting at once migrate one after the other (a
    lock on a file beside it); PostgreSQL takes its advisory lock in the transaction."""
    path = sqlite_file(engine)
    if path is None:
        yield
        return
    with file_lock(Path(f"{path}.migrating")):
        yield


def sqlite_file(engine: Engine) -> str | None:
    """The path of the engine's SQLite file; None for PostgreSQL or an in-memory SQLite."""
    path = engine.url.database
    if engine.dialect.name != "sqlite" or not path or path == ":memory:":
        return None
    return path


@contextmanager
def file_lock(path: Path) -> Iterator[None]:
    """An exclusive lock on ``path`` (created if missing) while in the block: between
    processes, and between threads (each opens the file itself). Waiting for it releases
    the GIL."""
    with path.open("a") as handle, _locked(handle):
        yield


@contextmanager
def _locked(handle: IO[str]) -> Iterator[None]:
    # portalocker's blocking lock, not its Lock class nor filelock's: those poll (every
    # 50 ms or so) where this waits in the kernel and wakes the moment the lock is free,
    # which is what kept the write tail short under load (docs/load-benchmark.md).
    portalocker.lock(handle, portalocker.LockFlags.EXCLUSIVE)
    try:
        yield
    finally:
        portalocker.unlock(handle)


class WriterLock:
    """One writer at a time on a SQLite file, across the threads and processes using it.

    SQLite itself takes one writer at a time, and a writer that finds the file locked
    sleeps and tries again (1 ms, then longer, up to 100 ms a time): under load, the
    writers of one process keep the file while another's sleep, for seconds. Here they
    wait in the kernel for a lock file instead, and get it as soon as it is free.
    """

    def __init__(self, path: str) -> None:
        self._path = Path(f"{path}.writing")
        self._threads = threading.Lock()  # this process's threads, one at a time

    @contextmanager
    def held(self) -> Iterator[None]:
        with self._threads:
            try:
                handle = self._path.open("a")
            except OSError as error:  # the database's folder is gone or unreadable
                raise DatabaseUnavailableError(f"{self._path.name}: {error.strerror}") from error
            with handle, _locked(handle):
                yield


class Database:
    """The engine with the three ways the repositories use it: :meth:`read` (an ORM
    session), :meth:`query` (a plain connection for prepared Core statements: no ORM work
    per call) and :meth:`write` (a transaction, one writer at a time on a SQLite file).
    Each raises :class:`DatabaseUnavailableError` while the database cannot be reached."""

    def __init__(self, engine: Engine) -> None:
        self.engine = engine
        self.postgresql = engine.dialect.name == "postgresql"
        self._sessions = sessionmaker(engine, expire_on_commit=False)
        # Reads outside a transaction on PostgreSQL (autocommit): each read is one statement,
        # which PostgreSQL runs on a snapshot of its own, and a transaction around it cost
        # two more round trips (BEGIN, ROLLBACK), more of PostgreSQL's CPU than the read.
        # SQLite begins no transaction for a read anyway.
        self._reads = (
            engine.execution_options(isolation_level="AUTOCOMMIT") if self.postgresql else engine
        )
        self._read_sessions = sessionmaker(self._reads, expire_on_commit=False)
        path = sqlite_file(engine)
        self._writer = None if path is None else WriterLock(path)

    @contextmanager
    def read(self) -> Iterator[Session]:
        """An ORM session for reading: each statement sees the database as it then is."""
        with translated(), self._read_sessions() as tx:
            yield tx

    @contextmanager
    def query(self) -> Iterator[Connection]:
        """A plain connection for reading: each statement sees the database as it then is."""
        with translated(), self._reads.connect() as connection:
            yield connection

    @contextmanager
    def write(self) -> Iterator[Session]:
        """A transaction, committed at the end of the block (rolled back on an error)."""
        with self.writing(), translated(), self._sessions.begin() as tx:
            yield tx

    def writing(self) -> AbstractContextManager[None]:
        """Holds the writer lock of a SQLite file (PostgreSQL takes row locks itself)."""
        return nullcontext() if self._writer is None else self._writer.held()

    def answers(self) -> bool:
        """Whether the database answers a query."""
        with self.query() as connection:
            return connection.scalar(text("SELECT 1")) == 1


@contextmanager
def translated() -> Iterator[None]:
    """An unreachable database as :class:`DatabaseUnavailableError`; other errors unchanged."""
    try:
        yield
    except SQLAlchemyError as error:
        if unavailable(error):
            raise DatabaseUnavailableError(str(error).splitlines()[0]) from error
        raise


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
