"""The production topology run for real (``deploy/cluster.py``, as ``make run-cluster``):
phones reach two replicas only through Debian's nginx with ``deploy/nginx.conf``, over
HTTPS with the certificate made at start-up, on a throwaway PostgreSQL database.

Streams re-read the event table only every 30 s and ping every 20 s here, so an event that
reaches a stream within CROSSING_SECONDS was carried by LISTEN/NOTIFY and passed on by
nginx as it came, nothing else.
"""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx2
import pytest
from phones import (
    CROSSING_SECONDS,
    PAIR,
    REPLICA_ENV,
    TEMPLE,
    end,
    followed,
    in_region,
    joiner_tapping,
    kept,
    landmarks,
    scene_taps,
)

from deploy.cluster import Cluster, cluster
from deploy.postgres import PostgresServer
from testbed.client import Phone, live, pair, server_timing

ROLES = ("starter", "joiner")


@contextmanager
def started(folder: Path, postgres: PostgresServer, template: str) -> Iterator[Cluster]:
    """nginx -> 2 replicas -> a new PostgreSQL database; httpx2 trusts the certificate made
    at start-up."""
    database = postgres.create_database(template=template)
    try:
        with (
            cluster(folder, postgres.url(database), environment=REPLICA_ENV) as running,
            pytest.MonkeyPatch.context() as patch,
        ):
            assert running.authority is not None
            patch.setenv("SSL_CERT_FILE", str(running.authority))
            yield running
    finally:
        postgres.drop_database(database)


@pytest.fixture(scope="module")
def running(
    tmp_path_factory: pytest.TempPathFactory, postgres: PostgresServer, migrated_database: str
) -> Iterator[Cluster]:
    """One cluster for the tests that leave it whole (each has sessions of its own)."""
    with started(tmp_path_factory.mktemp("cluster"), postgres, migrated_database) as running:
        yield running


@pytest.fixture
def own(tmp_path: Path, postgres: PostgresServer, migrated_database: str) -> Iterator[Cluster]:
    """A cluster for one test, which may break it."""
    with started(tmp_path, postgres, migrated_database) as running:
        yield running


def test_streams_through_nginx_hear_changes_made_on_either_replica(running: Cluster) -> None:
    """Each phone's stream runs through nginx to one replica or the other; changes written
    straight on each replica in turn reach both streams at once, so each stream heard a
    change made on the replica it is not connected to."""
    starter, joiner, starter_events, joiner_events = followed(running.url)  # through nginx
    scene, taps = scene_taps()
    one, two = (replica.base_url for replica in running.replicas)
    on_one = Phone(live(one), starter.session_id, starter.token)
    on_two = Phone(live(two), joiner.session_id, joiner.token)

    on_one.uploaded(TEMPLE / f"{PAIR[0]}.png")
    for events in (starter_events, joiner_events):
        events.wait_for("photo", role="starter", seconds=CROSSING_SECONDS)
    on_two.uploaded(TEMPLE / f"{PAIR[1]}.png")
    for events in (starter_events, joiner_events):
        events.wait_for("photo", role="joiner", seconds=CROSSING_SECONDS)
    on_one.tapped(landmarks=landmarks(taps.landmarks1, sigma=2.0), friend=taps.epipole1)
    state = on_two.tapped(landmarks=landmarks(taps.landmarks2, sigma=2.0))
    for events in (starter_events, joiner_events):
        events.wait_for("answer", version=state["version"], seconds=CROSSING_SECONDS)

    answer = starter.state()["answer"]  # through nginx, from either replica: the same answer
    assert answer == state["answer"]
    assert in_region(answer["in_photo"]["joiner"]["region"], scene.epipole2)
    end(starter, starter_events, joiner_events)


def test_nginx_passes_each_event_on_as_it_comes(running: Cluster) -> None:
    """Events of a few dozen bytes, one at a time: each reaches the phone before the next
    is written. A proxy that buffered the stream would hold them until a buffer filled."""
    starter, joiner, starter_events, _ = followed(running.url)
    _, taps = scene_taps()
    joiner.uploaded(TEMPLE / f"{PAIR[1]}.png")
    starter_events.wait_for("photo", role="joiner", seconds=CROSSING_SECONDS)
    for n in range(1, 6):
        joiner.tapped(landmarks=landmarks(taps.landmarks2[:n], sigma=2.0))
        starter_events.wait_for("taps", count=n, role="joiner", seconds=CROSSING_SECONDS)
    assert starter_events.pings == 0  # nothing but the events themselves pushed them through
    end(starter, starter_events)


def test_a_replica_killed_under_nginx_loses_nothing(own: Cluster) -> None:
    """kill -9 one replica mid-search. The stream it held drops and the phone reconnects
    through nginx with its last event id, reaching the other replica; the other stream
    never notices; every call goes on answering; no event and no write is lost."""
    starter, joiner, starter_events, joiner_events = followed(own.url)
    scene, taps, before = joiner_tapping(starter, joiner, starter_events)

    os.kill(own.replicas[0].pid, signal.SIGKILL)
    time.sleep(CROSSING_SECONDS)
    streams = {"starter": starter_events, "joiner": joiner_events}
    # nginx took turns: the two streams, opened one after the other, went to both replicas.
    (dropped,) = [role for role, events in streams.items() if events.ended.is_set()]
    assert streams[dropped].dropped
    phone = {"starter": starter, "joiner": joiner}[dropped]
    resumed = phone.listen(last_event_id=streams[dropped].ids[-1])
    resumed.wait_for("joined", role=dropped, online=True)

    assert kept(starter) == before
    state = joiner.tapped(landmarks=landmarks(taps.landmarks2, sigma=2.0))  # the joiner finishes
    (steady,) = [events for role, events in streams.items() if role != dropped]
    assert not steady.dropped  # still the same connection
    for events in (resumed, steady):
        events.wait_for("answer", version=state["version"], seconds=CROSSING_SECONDS)
    answer = joiner.state()["answer"]
    assert in_region(answer["in_photo"]["joiner"]["region"], scene.epipole2)

    # Nothing lost: what the phone saw before and after the kill is every event of the
    # session from its first one on, as a stream opened now from the start replays them.
    replay = phone.listen(last_event_id=0)
    replay.wait_for("answer", version=state["version"])
    # Up to the replay's newest: the resumed stream may already have the event of a later
    # change (the replay's own connection is one: the phone online), which the replay
    # reaches only after the answer it was waited for; or it may not have that newest yet.
    newest = replay.ids[-1]
    resumed.wait_for_id(newest, seconds=CROSSING_SECONDS)
    seen = streams[dropped].ids + resumed.ids
    assert seen == sorted(set(seen))
    assert [i for i in seen if i <= newest] == [i for i in replay.ids if seen[0] <= i]
    end(starter, resumed, steady, replay)


def test_a_slow_upload_through_nginx_is_neither_cut_nor_holding_a_replica(
    running: Cluster,
) -> None:
    """A phone on a poor network sends its photo in dribbles over 6 s: nginx takes it all
    and passes it on at once, so the upload succeeds and the replica spends only the
    photo's own processing on it (its Server-Timing), not the 6 s."""
    starter, _ = pair(live(running.url))
    photo = TEMPLE / f"{PAIR[0]}.png"
    files = {"photo": (photo.name, photo.read_bytes(), "image/png")}
    form = starter.client.build_request("PUT", starter.url("/photo"), files=files)
    body = form.read()
    chunks = [body[i : i + len(body) // 12 + 1] for i in range(0, len(body), len(body) // 12 + 1)]

    def dribble() -> Iterator[bytes]:
        for chunk in chunks:
            time.sleep(0.5)
            yield chunk

    started = time.monotonic()
    answer = starter.call(
        "PUT", "/photo", content=dribble(), headers={"Content-Type": form.headers["Content-Type"]}
    )
    took = time.monotonic() - started
    assert answer.status_code == 200, answer.text
    assert took >= 0.5 * len(chunks)
    app_seconds = server_timing(answer.headers["Server-Timing"])["app"] / 1000
    assert app_seconds < took / 2
    assert starter.state()["photos"]["starter"] is not None
    assert starter.call("DELETE").status_code == 204


def test_bodies_up_to_the_apps_limit_reach_it_and_larger_get_the_apps_error_shape(
    running: Cluster,
) -> None:
    """nginx lets through every body the app accepts (30,000,000 bytes; its own limit is
    30 MiB), so the app refuses one just over its limit itself; nginx refuses larger ones,
    in the app's error shape, with HSTS like every answer over HTTPS."""
    starter, _ = pair(live(running.url))
    app_limit = 30_000_000
    for size, who in ((app_limit + 1, "app"), (31 * 1024 * 1024, "nginx")):
        answer = starter.call(
            "PUT", "/photo", content=b"\0" * size, headers={"Content-Type": "image/jpeg"}
        )
        assert answer.status_code == 413, (who, answer.text)
        assert answer.json()["error"]["code"] == "body_too_large", who
        assert answer.headers.get_list("Strict-Transport-Security") == ["max-age=31536000"]
        assert ("server-timing" in answer.headers) == (who == "app")
    assert starter.call("DELETE").status_code == 204


def test_plain_http_leads_to_https_which_carries_hsts_once(running: Cluster) -> None:
    """A phone typing the address gets sent to HTTPS; every answer there says to stay on it
    (nginx's header; the app's own copy dropped), and join links point back to it."""
    redirect = httpx2.get(f"{running.http_url}/join/12345678?x=1")
    assert redirect.status_code == 301
    assert redirect.headers["Location"] == f"{running.url}/join/12345678?x=1"
    created = httpx2.post(f"{running.url}/api/sessions")
    assert created.status_code == 201
    assert created.headers.get_list("Strict-Transport-Security") == ["max-age=31536000"]
    assert created.json()["join_url"].startswith(f"{running.url}/join/")
