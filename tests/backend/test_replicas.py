"""Two replicas of the app, two uvicorn processes sharing nothing but a PostgreSQL server:
the two phones on different replicas find each other, events cross between them, and the
search survives a replica killed and PostgreSQL restarted. Also two worker processes on
one SQLite file, whose events cross by each process's watcher."""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path

import httpx2
import psycopg
import pytest
from phones import (
    CROSSING_SECONDS,
    REPLICA_ENV,
    end,
    error_of,
    followed,
    in_region,
    joiner_tapping,
    kept,
    landmarks,
    photos_and_taps_cross,
)
from sqlalchemy.engine import make_url

from deploy.postgres import PostgresServer
from deploy.replica import Server, serve
from testbed.client import Phone, live


@contextmanager
def two_servers(folder: Path, url: str, name: str) -> Iterator[tuple[Server, Server]]:
    """Two uvicorn processes on two loopback ports (``name`` 1 and 2, each in its own
    folder), on the same database."""
    environment = {"BUDDY_DATABASE_URL": url, **REPLICA_ENV}
    with ExitStack() as stack:
        servers = []
        for n in (1, 2):
            (folder / f"{name}{n}").mkdir()
            servers.append(stack.enter_context(serve(folder / f"{name}{n}", environment)))
        yield servers[0], servers[1]


@pytest.fixture
def replicas(tmp_path: Path, fresh_postgres_url: str) -> Iterator[tuple[Server, Server]]:
    """Two replicas on the same PostgreSQL database."""
    with two_servers(tmp_path, fresh_postgres_url, "replica") as servers:
        yield servers


def test_phones_on_two_replicas_find_each_other(
    replicas: tuple[Server, Server], postgres: PostgresServer, fresh_postgres_url: str
) -> None:
    one, two = replicas
    starter, joiner, starter_events, joiner_events = followed(one.base_url, two.base_url)

    scene, state = photos_and_taps_cross(starter, joiner, starter_events, joiner_events)

    # Both replicas tell the same state, drawn from the same photos.
    answer = state["answer"]
    assert in_region(answer["in_photo"]["joiner"]["region"], scene.epipole2)
    assert starter.state()["answer"] == answer
    overlays = [phone.call("GET", "/overlay/joiner").content for phone in (starter, joiner)]
    assert overlays[0] == overlays[1]

    # The control: an event written without a notification waits for the poll (30 s), and
    # the notification alone delivers it at once. So NOTIFY is what carried the others.
    name = make_url(fresh_postgres_url).database or ""
    with psycopg.connect(postgres.conninfo(name), autocommit=True) as database:
        database.execute(
            "INSERT INTO events (session_id, type, data, created_at) "
            "VALUES (%s, 'joined', '{\"role\": \"control\"}', now())",
            (starter.session_id,),
        )
        time.sleep(CROSSING_SECONDS)
        assert starter_events.count("joined", role="control") == 0
        database.execute("SELECT pg_notify('buddy_events', %s)", (starter.session_id,))
        starter_events.wait_for("joined", role="control", seconds=CROSSING_SECONDS)

    # Delete now, on replica 1: the joiner's stream on replica 2 ends at once.
    end(starter, joiner_events, starter_events)
    assert starter_events.ids == sorted(starter_events.ids)
    assert not starter_events.dropped
    assert not joiner_events.dropped


def test_two_processes_on_one_sqlite_file_see_each_others_changes(tmp_path: Path) -> None:
    """No LISTEN/NOTIFY on SQLite: each process's watcher (4 times a second) wakes its
    streams for the other's changes, and ends them when the other deletes the session.
    Streams poll every 30 s here, so delivery within CROSSING_SECONDS is the watcher's."""
    with two_servers(tmp_path, f"sqlite:///{tmp_path / 'buddy.db'}", "worker") as servers:
        urls = (server.base_url for server in servers)
        starter, joiner, starter_events, joiner_events = followed(*urls)
        _, state = photos_and_taps_cross(starter, joiner, starter_events, joiner_events)
        assert starter.state()["answer"] == state["answer"]
        end(starter, joiner_events)
        assert not starter_events.dropped
        assert not joiner_events.dropped


def test_a_replica_killed_mid_search_loses_nothing(replicas: tuple[Server, Server]) -> None:
    one, two = replicas
    starter, joiner, starter_events, joiner_events = followed(one.base_url, two.base_url)
    scene, taps, before = joiner_tapping(starter, joiner, starter_events)

    os.kill(one.pid, signal.SIGKILL)  # no shutdown, no goodbye
    assert starter_events.ended.wait(10)
    assert starter_events.dropped

    # The starter's phone reconnects to replica 2 with the same token, from its last event.
    starter = Phone(live(two.base_url), starter.session_id, starter.token, starter.role)
    assert kept(starter) == before  # photos, taps and version
    assert before[0]["taps"]["starter"]["landmarks"] == landmarks(taps.landmarks1, sigma=2.0)
    resumed = starter.listen(last_event_id=starter_events.ids[-1])
    resumed.wait_for("joined", role="starter", online=True)

    state = joiner.tapped(landmarks=landmarks(taps.landmarks2, sigma=2.0))  # the joiner finishes
    resumed.wait_for("answer", version=state["version"], seconds=CROSSING_SECONDS)
    answer = starter.state()["answer"]
    assert in_region(answer["in_photo"]["joiner"]["region"], scene.epipole2)
    # The joiner's stream on replica 2 never noticed: still the same connection.
    joiner_events.wait_for("answer", version=state["version"])
    assert not joiner_events.dropped
    assert not joiner_events.ended.is_set()
    end(starter, resumed, joiner_events)


def test_postgresql_restarted_mid_search(
    replicas: tuple[Server, Server], postgres: PostgresServer
) -> None:
    one, two = replicas
    starter, joiner, starter_events, joiner_events = followed(one.base_url, two.base_url)
    scene, taps, _ = joiner_tapping(starter, joiner, starter_events)
    joiner_events.wait_for("taps", role="starter")

    postgres.stop()
    try:
        for replica, phone in ((one, starter), (two, joiner)):
            health = httpx2.get(f"{replica.base_url}/healthz", timeout=10)
            refused = phone.call("PUT", "/taps", json={"landmarks": []})
            for answer in (health, phone.call("GET"), refused):
                assert error_of(answer, 503) == "database_unavailable"
    finally:
        postgres.start()

    for replica in (one, two):  # back by themselves, neither restarted
        wait_until_healthy(replica)
        os.kill(replica.pid, 0)  # still the same process
    state = joiner.tapped(landmarks=landmarks(taps.landmarks2, sigma=2.0))
    starter_events.wait_for("answer", version=state["version"], seconds=CROSSING_SECONDS)
    assert starter.state()["answer"] == state["answer"]
    assert in_region(state["answer"]["in_photo"]["joiner"]["region"], scene.epipole2)
    # The streams lived through it: the same connections, no reconnection.
    for events in (starter_events, joiner_events):
        assert not events.dropped
        assert not events.ended.is_set()
    end(joiner, starter_events, joiner_events)


def wait_until_healthy(replica: Server, seconds: float = 20) -> None:
    deadline = time.monotonic() + seconds
    while httpx2.get(f"{replica.base_url}/healthz", timeout=10).status_code != 200:
        assert time.monotonic() < deadline, f"{replica.base_url} did not recover"
        time.sleep(0.1)
