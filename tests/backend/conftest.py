"""Fixtures for the service: an app on a fresh database (each test runs twice: on a SQLite
file, and on a database of a throwaway PostgreSQL server, unless its ``databases`` marker
names one), a controllable clock, and two phones already paired."""

from __future__ import annotations

import functools
import shutil
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager, contextmanager
from pathlib import Path

import psycopg
import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient
from phones import TEMPLE_PHOTOS, FakeClock, Phones, joined, photos_uploaded
from psycopg import sql
from sqlalchemy.engine import make_url

from backend.main import create_app
from backend.settings import Settings
from backend.storage.database import make_engine
from backend.wiring import Services
from deploy.postgres import PostgresServer
from testbed.client import Phone, start

DATABASES = ("sqlite", "postgresql")


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    """``database_url``: the databases the test's ``databases`` marker names, else both. A
    module that checks nothing storage does names SQLite alone (the stateless solver
    endpoints; guidance's image matching, whose taps and photos are stored as those of
    test_sessions.py are): on PostgreSQL it ran the same code again."""
    if "database_url" in metafunc.fixturenames:
        marker = metafunc.definition.get_closest_marker("databases")
        names = marker.args if marker else DATABASES
        assert names, "name a database"
        assert set(names) <= set(DATABASES), names
        metafunc.parametrize("database_url", names, indirect=True)


@pytest.fixture(scope="session")
def postgres() -> Iterator[PostgresServer]:
    """One PostgreSQL server for the whole run, on a free loopback port."""
    server = PostgresServer()
    try:
        server.start()
        yield server
    finally:
        server.remove()


@pytest.fixture(scope="session")
def migrated_database(postgres: PostgresServer) -> str:
    """A database migrated once, which each test's database is a copy of."""
    name = postgres.create_database()
    make_engine(postgres.url(name)).dispose()
    return name


@pytest.fixture(scope="session")
def spare_databases() -> list[str]:
    """Databases a test used and :func:`emptied` left as the template is, for the next."""
    return []


@pytest.fixture
def fresh_postgres_url(
    postgres: PostgresServer, migrated_database: str, spare_databases: list[str]
) -> Iterator[str]:
    """The URL of an empty, migrated PostgreSQL database: one an earlier test used, emptied,
    or else a new copy of the template. (A copy took 310 ms here, the emptying a few: the
    PostgreSQL half of the backend's tests spent more time getting a database than testing.)
    A database that cannot be emptied back to the template's state is dropped."""
    name = spare_databases.pop() if spare_databases else None
    name = name or postgres.create_database(template=migrated_database)
    yield postgres.url(name)
    if emptied(postgres, name, migrated_database):
        spare_databases.append(name)
    else:
        postgres.drop_database(name)


def emptied(postgres: PostgresServer, name: str, template: str) -> bool:
    """Empty ``name`` as ``template`` is (its tables' rows gone, their identities restarted)
    if its tables and migration are the template's; whether it was. Whoever is still
    connected (a server the test left running) is disconnected first."""
    try:
        with psycopg.connect(postgres.conninfo(name), autocommit=True) as connection:
            connection.execute(
                "SELECT pg_terminate_backend(pid) FROM pg_stat_activity"
                " WHERE datname = %s AND pid <> pg_backend_pid()",
                (name,),
            )
            layout = _layout(connection)
            if layout != _template_layout(postgres, template):
                return False
            connection.execute("SET lock_timeout = '5s'")
            tables = [t for t in layout[0] if t != "alembic_version"]
            names = sql.SQL(", ").join(sql.Identifier(t) for t in tables)
            connection.execute(sql.SQL("TRUNCATE {} RESTART IDENTITY CASCADE").format(names))
    except psycopg.Error:
        return False
    return True


Layout = tuple[tuple[str, ...], tuple[str, ...]]


def _layout(connection: psycopg.Connection[tuple[str]]) -> Layout:
    """A database's tables and its migration."""
    tables = connection.execute(
        "SELECT tablename FROM pg_tables WHERE schemaname = 'public' ORDER BY 1"
    ).fetchall()
    version = connection.execute("SELECT version_num FROM alembic_version").fetchall()
    return tuple(t for (t,) in tables), tuple(v for (v,) in version)


@functools.cache
def _template_layout(postgres: PostgresServer, template: str) -> Layout:
    with psycopg.connect(postgres.conninfo(template), autocommit=True) as connection:
        return _layout(connection)


@pytest.fixture(scope="session")
def migrated_sqlite(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A SQLite file migrated once, which each test's SQLite database is a copy of (migrating
    a new file was most of the app's start: 0.12 s, against 0.02 s on a copy)."""
    path = tmp_path_factory.mktemp("sqlite-template") / "buddy.db"
    make_engine(f"sqlite:///{path}").dispose()
    return path


@pytest.fixture
def database_url(request: pytest.FixtureRequest, tmp_path: Path) -> str:
    """A fresh database, SQLite or PostgreSQL (``pytest_generate_tests``)."""
    if request.param == "sqlite":
        folder = tmp_path / "database"
        folder.mkdir()
        shutil.copyfile(request.getfixturevalue("migrated_sqlite"), folder / "buddy.db")
        return f"sqlite:///{folder / 'buddy.db'}"
    url: str = request.getfixturevalue("fresh_postgres_url")
    return url


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def database_outage(
    request: pytest.FixtureRequest, app: FastAPI, database_url: str
) -> Callable[[], AbstractContextManager[None]]:
    """``with database_outage():`` the app's database cannot be reached. PostgreSQL: the
    server is stopped, then started again. SQLite: its folder is moved away (the app's
    pooled connections closed first), then back."""

    @contextmanager
    def outage() -> Iterator[None]:
        if database_url.startswith("postgresql"):
            postgres: PostgresServer = request.getfixturevalue("postgres")
            postgres.stop()
            try:
                yield
            finally:
                postgres.start()
            return
        folder = Path(make_url(database_url).database or "").parent
        app.state.services.database.engine.dispose()
        folder.rename(folder.with_name("away"))
        try:
            yield
        finally:
            folder.with_name("away").rename(folder)

    return outage


@pytest.fixture
def settings(database_url: str) -> Settings:
    return Settings(database_url=database_url, sweep_interval_seconds=3600)


@pytest.fixture
def app(settings: Settings, clock: FakeClock) -> FastAPI:
    return create_app(settings, clock)


@pytest.fixture
def client(app: FastAPI) -> Iterator[TestClient]:
    with TestClient(app, raise_server_exceptions=False) as test_client:
        yield test_client


@pytest.fixture
def services(client: TestClient) -> Services:
    """The running app's services: its stores, streams and sweeper, behind the API."""
    found: Services = client.app.state.services  # type: ignore[attr-defined]
    return found


@pytest.fixture
def starter(client: TestClient) -> Phone:
    return start(client)[0]


@pytest.fixture
def joiner(client: TestClient, starter: Phone) -> Phone:
    return joined(client, starter.state()["join_code"])


@pytest.fixture
def temple_photos() -> tuple[bytes, bytes]:
    """The facing temple pair as uploaded by the two phones (PNG, 640x480)."""
    return TEMPLE_PHOTOS


@pytest.fixture
def uploaded(starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]) -> Phones:
    """The two phones, each with its temple photo uploaded."""
    photos_uploaded(starter, joiner, temple_photos)
    return starter, joiner
