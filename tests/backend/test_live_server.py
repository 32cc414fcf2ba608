"""The whole two-phone flow against a real uvicorn process on loopback, events included."""

from __future__ import annotations

import time
import zlib
from collections.abc import Iterator
from pathlib import Path

import httpx2
import numpy as np
import pytest
from phones import (
    PAIR,
    TEMPLE,
    end,
    image_of,
    in_region,
    joined,
    landmarks,
    photos_and_taps_cross,
)

from deploy.replica import serve
from testbed.client import Phone, live, start


@pytest.fixture
def server(tmp_path: Path, database_url: str) -> Iterator[str]:
    """uvicorn serving backend.main:app on a free loopback port; its base URL."""
    with serve(tmp_path, {"BUDDY_DATABASE_URL": database_url}) as running:
        yield running.base_url


def test_two_phones_find_each_other(server: str) -> None:
    http = live(server)
    created = http.post("/api/sessions").json()
    starter = Phone(http, created["session_id"], created["token"], "starter")
    starter_events = starter.listen()
    starter_events.wait_for("joined")  # its own presence

    # The joiner opens the join link: the code is its last part.
    joiner = joined(http, created["join_url"].rsplit("/", 1)[-1])
    joiner_events = joiner.listen()
    starter_events.wait_for("joined", 3)  # joiner joined, joiner online

    scene, state = photos_and_taps_cross(starter, joiner, starter_events, joiner_events, 15)
    starter_events.wait_for("photo", 2)
    joiner_events.wait_for("answer")

    answer = state["answer"]
    assert answer["method"] == "pinhole_epipole"  # phone cameras: the camera model answers
    assert in_region(answer["in_photo"]["joiner"]["region"], scene.epipole2)
    assert starter.state()["answer"] == answer

    for role in ("starter", "joiner"):
        assert image_of(joiner.call("GET", f"/overlay/{role}")).shape == (480, 640, 3)

    assert starter_events.ids == sorted(starter_events.ids)
    assert {"joined", "photo", "taps", "answer"} <= set(starter_events.types)
    end(starter, starter_events, joiner_events, seconds=15)


def test_answers_and_events_come_gzipped_each_event_readable_when_sent(server: str) -> None:
    """A phone asks for gzip: JSON comes compressed, a photo (JPEG) as it is; the event
    stream compressed too, but each write flushed: its first bytes at once and each event
    readable from the bytes that came, before anything follows."""
    http = live(server)
    gzip = {"Accept-Encoding": "gzip"}
    starter = start(http)[0]
    assert http.get("/openapi.json", headers=gzip).headers["content-encoding"] == "gzip"
    plain = http.get("/openapi.json", headers={"Accept-Encoding": "identity"})
    assert "content-encoding" not in plain.headers
    starter.uploaded(TEMPLE / f"{PAIR[0]}.png")
    photo = starter.call("GET", "/photo/starter", headers=gzip)
    assert photo.headers["content-type"] == "image/jpeg"
    assert "content-encoding" not in photo.headers

    url = str(http.base_url).rstrip("/") + starter.url("/events")
    with httpx2.stream("GET", url, params={"token": starter.token}, headers=gzip) as stream:
        assert stream.headers["content-encoding"] == "gzip"
        assert "Accept-Encoding" in stream.headers["vary"]
        # The raw bytes, inflated here as they come: one gzip stream, never ended by itself.
        gunzip = zlib.decompressobj(16 + zlib.MAX_WBITS)
        chunks = stream.iter_raw()
        text = ""
        while "event: joined" not in text:
            text += gunzip.decompress(next(chunks)).decode()
        assert text.startswith("retry: ")
        starter.tapped(landmarks=landmarks(np.array([[10.0, 20.0]])))
        sent = len(text)
        raw = 0
        while "event: taps" not in text:
            chunk = next(chunks)
            raw += len(chunk)
            text += gunzip.decompress(chunk).decode()
        assert raw < len(text) - sent  # compressed

    identity = {"Accept-Encoding": "identity"}
    with httpx2.stream("GET", url, params={"token": starter.token}, headers=identity) as plain:
        assert "content-encoding" not in plain.headers
        assert next(plain.iter_raw()).startswith(b"retry: ")


def test_the_server_stops_promptly_with_a_phone_listening(
    tmp_path: Path, database_url: str
) -> None:
    """Event streams never end by themselves: stopping (SIGTERM) must not wait for them
    (nor for the thread listening to PostgreSQL)."""
    with serve(tmp_path, {"BUDDY_DATABASE_URL": database_url}) as running:
        http = live(running.base_url)
        listener = start(http)[0].listen()
        listener.wait_for("joined")
        stopping = time.monotonic()
    assert time.monotonic() - stopping < 10  # the 3 s grace, not the 20 s kill
    assert listener.ended.wait(5)
    assert listener.dropped
