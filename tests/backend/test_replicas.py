"""Two replicas of the app, two uvicorn processes sharing nothing but a PostgreSQL server:
the two phones on different replicas find each other, events cross between them, and the
search survives a replica killed and PostgreSQL restarted. Also two worker processes on
one SQLite file, whose events cross by each process's watcher."""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Iterator
from contextlib import ExitStack
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import psycopg
import pytest
from phones import PAIR, HttpPhone, Listener, follow, landmarks, pair, scene_taps
from postgres import PostgresServer

from backend.loopback import Server, serve
from backend.storage.database import database_url
from shared_solver.estimation.uncertainty import contains
from testbed.scenes import Scene

# Streams read the event table only when woken or every 30 s, and ping every 20 s: an
# event that reaches the other replica's stream within CROSSING_SECONDS was carried by
# LISTEN/NOTIFY, nothing else.
REPLICA_ENV = {"BUDDY_EVENT_POLL_SECONDS": "30", "BUDDY_KEEPALIVE_SECONDS": "20"}
CROSSING_SECONDS = 2.0


@pytest.fixture
def replicas(tmp_path: Path, fresh_postgres_url: str) -> Iterator[tuple[Server, Server]]:
    """Two uvicorn processes on two loopback ports, on the same PostgreSQL database."""
    environment = {"BUDDY_DATABASE_URL": fresh_postgres_url, **REPLICA_ENV}
    with ExitStack() as stack:
        servers = []
        for name in ("replica1", "replica2"):
            (tmp_path / name).mkdir()
            servers.append(stack.enter_context(serve(tmp_path / name, environment)))
        yield servers[0], servers[1]


def photos_and_taps_cross(
    seeker: HttpPhone, buddy: HttpPhone, seeker_events: Listener, buddy_events: Listener
) -> tuple[Scene, dict[str, Any]]:
    """Both photos and both tap sets, each phone on its own process: each change reaches
    the other phone's stream within CROSSING_SECONDS. The scene, and the buddy's state with
    the answer (computed in the buddy's process)."""
    seeker.upload(PAIR[0])
    buddy_events.wait_for("photo", role="seeker", seconds=CROSSING_SECONDS)
    buddy.upload(PAIR[1])
    seeker_events.wait_for("photo", role="buddy", seconds=CROSSING_SECONDS)
    scene, taps = scene_taps()
    seeker.tap(landmarks=landmarks(taps.landmarks1), epipole1=taps.epipole1.tolist())
    buddy_events.wait_for("taps", role="seeker", seconds=CROSSING_SECONDS)
    state = buddy.tap(landmarks=landmarks(taps.landmarks2))
    seeker_events.wait_for("taps", role="buddy", seconds=CROSSING_SECONDS)
    seeker_events.wait_for("result", version=state["version"], seconds=CROSSING_SECONDS)
    return scene, state


def test_phones_on_two_replicas_find_each_other(
    replicas: tuple[Server, Server], postgres: PostgresServer, fresh_postgres_url: str
) -> None:
    one, two = replicas
    seeker, buddy = pair(one.base_url, two.base_url)
    seeker_events, buddy_events = follow(seeker, buddy, CROSSING_SECONDS)

    scene, state = photos_and_taps_cross(seeker, buddy, seeker_events, buddy_events)

    # Both replicas tell the same state, drawn from the same photos.
    result = state["result"]
    covariance = np.array(result["uncertainty"]["covariance"])
    assert contains(np.array(result["epipole2"]), covariance, scene.epipole2)
    assert seeker.state()["result"] == result
    assert (
        seeker.call("GET", "/overlay/buddy").content == buddy.call("GET", "/overlay/buddy").content
    )

    # The control: an event written without a notification waits for the poll (30 s), and
    # the notification alone delivers it at once. So NOTIFY is what carried the others.
    with psycopg.connect(conninfo(fresh_postgres_url), autocommit=True) as database:
        database.execute(
            "INSERT INTO events (session_id, type, data, created_at) "
            "VALUES (%s, 'joined', '{\"role\": \"control\"}', now())",
            (seeker.session_id,),
        )
        time.sleep(CROSSING_SECONDS)
        assert seeker_events.count("joined", role="control") == 0
        database.execute("SELECT pg_notify('buddy_events', %s)", (seeker.session_id,))
        seeker_events.wait_for("joined", role="control", seconds=CROSSING_SECONDS)

    # Delete now, on replica 1: the buddy's stream on replica 2 ends at once.
    assert seeker.call("DELETE").status_code == 204
    assert buddy_events.ended.wait(CROSSING_SECONDS)
    assert buddy_events.types[-1] == "expired"
    assert seeker_events.ended.wait(CROSSING_SECONDS)
    assert seeker_events.ids == sorted(seeker_events.ids)
    assert not seeker_events.dropped
    assert not buddy_events.dropped


def test_two_processes_on_one_sqlite_file_see_each_others_changes(tmp_path: Path) -> None:
    """No LISTEN/NOTIFY on SQLite: each process's watcher (4 times a second) wakes its
    streams for the other's changes, and ends them when the other deletes the session.
    Streams poll every 30 s here, so delivery within CROSSING_SECONDS is the watcher's."""
    environment = {"BUDDY_DATABASE_URL": f"sqlite:///{tmp_path / 'buddy.db'}", **REPLICA_ENV}
    with ExitStack() as stack:
        servers = []
        for name in ("worker1", "worker2"):
            (tmp_path / name).mkdir()
            servers.append(stack.enter_context(serve(tmp_path / name, environment)))
        seeker, buddy = pair(*(server.base_url for server in servers))
        seeker_events, buddy_events = follow(seeker, buddy, CROSSING_SECONDS)
        _, state = photos_and_taps_cross(seeker, buddy, seeker_events, buddy_events)
        assert seeker.state()["result"] == state["result"]
        assert seeker.call("DELETE").status_code == 204
        assert buddy_events.ended.wait(CROSSING_SECONDS)
        assert buddy_events.types[-1] == "expired"
        assert not seeker_events.dropped
        assert not buddy_events.dropped


def test_a_replica_killed_mid_search_loses_nothing(replicas: tuple[Server, Server]) -> None:
    one, two = replicas
    seeker, buddy = pair(one.base_url, two.base_url)
    seeker_events, buddy_events = follow(seeker, buddy, CROSSING_SECONDS)
    seeker.upload(PAIR[0])
    buddy.upload(PAIR[1])
    scene, taps = scene_taps()
    seeker_taps = {"landmarks": landmarks(taps.landmarks1), "epipole1": taps.epipole1.tolist()}
    seeker.tap(**seeker_taps)
    buddy.tap(landmarks=landmarks(taps.landmarks2[:3]))  # the buddy is still tapping
    seeker_events.wait_for("taps", role="buddy", seconds=CROSSING_SECONDS)
    before = seeker.state()
    photos = [seeker.call("GET", f"/photo/{role}").content for role in ("seeker", "buddy")]

    os.kill(one.pid, signal.SIGKILL)  # no shutdown, no goodbye
    assert seeker_events.ended.wait(10)
    assert seeker_events.dropped

    # The seeker's phone reconnects to replica 2 with the same token, from its last event.
    seeker.base = two.base_url
    after = seeker.state()
    assert after["photos"] == before["photos"]
    assert [seeker.call("GET", f"/photo/{role}").content for role in ("seeker", "buddy")] == photos
    assert after["taps"] == before["taps"]
    assert after["taps"]["seeker"]["landmarks"] == seeker_taps["landmarks"]
    assert after["version"] == before["version"]
    resumed = seeker.listen(last_event_id=seeker_events.ids[-1])
    resumed.wait_for("joined", role="seeker", online=True)

    state = buddy.tap(landmarks=landmarks(taps.landmarks2))  # the buddy finishes
    resumed.wait_for("result", version=state["version"], seconds=CROSSING_SECONDS)
    result = seeker.state()["result"]
    covariance = np.array(result["uncertainty"]["covariance"])
    assert contains(np.array(result["epipole2"]), covariance, scene.epipole2)
    # The buddy's stream on replica 2 never noticed: still the same connection.
    buddy_events.wait_for("result", version=state["version"])
    assert not buddy_events.dropped
    assert not buddy_events.ended.is_set()
    end(seeker, resumed, buddy_events)


def test_postgresql_restarted_mid_search(
    replicas: tuple[Server, Server], postgres: PostgresServer
) -> None:
    one, two = replicas
    seeker, buddy = pair(one.base_url, two.base_url)
    seeker_events, buddy_events = follow(seeker, buddy, CROSSING_SECONDS)
    seeker.upload(PAIR[0])
    buddy.upload(PAIR[1])
    scene, taps = scene_taps()
    seeker.tap(landmarks=landmarks(taps.landmarks1), epipole1=taps.epipole1.tolist())
    buddy_events.wait_for("taps", role="seeker")

    postgres.stop()
    try:
        for replica, phone in ((one, seeker), (two, buddy)):
            health = httpx.get(f"{replica.base_url}/healthz", timeout=10)
            refused = phone.call("PUT", "/taps", json={"landmarks": []})
            for answer in (health, phone.call("GET"), refused):
                assert answer.status_code == 503, answer.text
                assert answer.json()["error"]["code"] == "database_unavailable"
    finally:
        postgres.start()

    for replica in (one, two):  # back by themselves, neither restarted
        wait_until_healthy(replica)
        os.kill(replica.pid, 0)  # still the same process
    state = buddy.tap(landmarks=landmarks(taps.landmarks2))
    seeker_events.wait_for("result", version=state["version"], seconds=CROSSING_SECONDS)
    assert seeker.state()["result"] == state["result"]
    assert contains(
        np.array(state["result"]["epipole2"]),
        np.array(state["result"]["uncertainty"]["covariance"]),
        scene.epipole2,
    )
    # The streams lived through it: the same connections, no reconnection.
    for events in (seeker_events, buddy_events):
        assert not events.dropped
        assert not events.ended.is_set()
    end(buddy, seeker_events, buddy_events)


def end(phone: HttpPhone, *streams: Listener) -> None:
    """Delete now: every stream of the session ends (and the replicas stop promptly)."""
    assert phone.call("DELETE").status_code == 204
    for stream in streams:
        assert stream.ended.wait(CROSSING_SECONDS)
        assert stream.types[-1] == "expired"


def wait_until_healthy(replica: Server, seconds: float = 20) -> None:
    deadline = time.monotonic() + seconds
    while httpx.get(f"{replica.base_url}/healthz", timeout=10).status_code != 200:
        assert time.monotonic() < deadline, f"{replica.base_url} did not recover"
        time.sleep(0.1)


def conninfo(url: str) -> str:
    """libpq's form of an app database URL."""
    return database_url(url).set(drivername="postgresql").render_as_string(hide_password=False)
