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
from typing import Any

import httpx2
import psycopg
import pytest
from phones import (
    CROSSING_SECONDS,
    PAIR,
    REPLICA_ENV,
    TEMPLE,
    end,
    error_of,
    in_region,
    landmarks,
    scene_taps,
)

from backend.storage.database import database_url
from deploy.postgres import PostgresServer
from deploy.replica import Server, serve
from testbed.client import Listener, Phone, follow, live, pair
from testbed.scenes import Scene


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


def photos_and_taps_cross(
    starter: Phone, joiner: Phone, starter_events: Listener, joiner_events: Listener
) -> tuple[Scene, dict[str, Any]]:
    """Both photos and both tap sets, each phone on its own process: each change reaches
    the other phone's stream within CROSSING_SECONDS. The scene, and the joiner's state with
    the answer (computed in the joiner's process)."""
    starter.uploaded(TEMPLE / f"{PAIR[0]}.png")
    joiner_events.wait_for("photo", role="starter", seconds=CROSSING_SECONDS)
    joiner.uploaded(TEMPLE / f"{PAIR[1]}.png")
    starter_events.wait_for("photo", role="joiner", seconds=CROSSING_SECONDS)
    scene, taps = scene_taps()
    starter.tapped(landmarks=landmarks(taps.landmarks1, sigma=2.0), friend=taps.epipole1)
    joiner_events.wait_for("taps", role="starter", seconds=CROSSING_SECONDS)
    state = joiner.tapped(landmarks=landmarks(taps.landmarks2, sigma=2.0))
    starter_events.wait_for("taps", role="joiner", seconds=CROSSING_SECONDS)
    starter_events.wait_for("answer", version=state["version"], seconds=CROSSING_SECONDS)
    return scene, state


def test_phones_on_two_replicas_find_each_other(
    replicas: tuple[Server, Server], postgres: PostgresServer, fresh_postgres_url: str
) -> None:
    one, two = replicas
    starter, joiner = pair(live(one.base_url), live(two.base_url))
    starter_events, joiner_events = follow(starter, joiner, CROSSING_SECONDS)

    scene, state = photos_and_taps_cross(starter, joiner, starter_events, joiner_events)

    # Both replicas tell the same state, drawn from the same photos.
    answer = state["answer"]
    assert in_region(answer["in_photo"]["joiner"]["region"], scene.epipole2)
    assert starter.state()["answer"] == answer
    assert (
        starter.call("GET", "/overlay/joiner").content
        == joiner.call("GET", "/overlay/joiner").content
    )

    # The control: an event written without a notification waits for the poll (30 s), and
    # the notification alone delivers it at once. So NOTIFY is what carried the others.
    with psycopg.connect(conninfo(fresh_postgres_url), autocommit=True) as database:
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
        starter, joiner = pair(live(servers[0].base_url), live(servers[1].base_url))
        starter_events, joiner_events = follow(starter, joiner, CROSSING_SECONDS)
        _, state = photos_and_taps_cross(starter, joiner, starter_events, joiner_events)
        assert starter.state()["answer"] == state["answer"]
        end(starter, joiner_events)
        assert not starter_events.dropped
        assert not joiner_events.dropped


def photos_taken(one: Server, two: Server) -> tuple[Phone, Phone, Listener, Listener]:
    """A search begun on replica one, joined on two: both streams open, both photos up."""
    starter, joiner = pair(live(one.base_url), live(two.base_url))
    starter_events, joiner_events = follow(starter, joiner, CROSSING_SECONDS)
    starter.uploaded(TEMPLE / f"{PAIR[0]}.png")
    joiner.uploaded(TEMPLE / f"{PAIR[1]}.png")
    return starter, joiner, starter_events, joiner_events


def test_a_replica_killed_mid_search_loses_nothing(replicas: tuple[Server, Server]) -> None:
    one, two = replicas
    starter, joiner, starter_events, joiner_events = photos_taken(one, two)
    scene, taps = scene_taps()
    starter_taps = {"landmarks": landmarks(taps.landmarks1, sigma=2.0), "friend": taps.epipole1}
    starter.tapped(**starter_taps)
    # The joiner is still tapping.
    joiner.tapped(landmarks=landmarks(taps.landmarks2[:3], sigma=2.0))
    starter_events.wait_for("taps", role="joiner", seconds=CROSSING_SECONDS)
    before = starter.state()
    photos = [starter.call("GET", f"/photo/{role}").content for role in ("starter", "joiner")]

    os.kill(one.pid, signal.SIGKILL)  # no shutdown, no goodbye
    assert starter_events.ended.wait(10)
    assert starter_events.dropped

    # The starter's phone reconnects to replica 2 with the same token, from its last event.
    starter = Phone(live(two.base_url), starter.session_id, starter.token, starter.role)
    after = starter.state()
    assert after["photos"] == before["photos"]
    assert [
        starter.call("GET", f"/photo/{role}").content for role in ("starter", "joiner")
    ] == photos
    assert after["taps"] == before["taps"]
    assert after["taps"]["starter"]["landmarks"] == starter_taps["landmarks"]
    assert after["version"] == before["version"]
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
    starter, joiner, starter_events, joiner_events = photos_taken(one, two)
    scene, taps = scene_taps()
    starter.tapped(landmarks=landmarks(taps.landmarks1, sigma=2.0), friend=taps.epipole1)
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


def conninfo(url: str) -> str:
    """libpq's form of an app database URL."""
    return database_url(url).set(drivername="postgresql").render_as_string(hide_password=False)
