"""The event stream: each change reaches the other phone, with ids to resume from."""

from __future__ import annotations

import json
import time
from collections.abc import AsyncGenerator, AsyncIterator, Callable, Sequence
from contextlib import AbstractContextManager, aclosing
from datetime import datetime
from typing import Any
from unittest.mock import ANY

import anyio
import pytest
from fastapi.sse import format_sse_event
from fastapi.testclient import TestClient
from phones import FakeClock, joined, landmarks, scene

from backend.eventstream.log import Event
from backend.eventstream.stream import EventStreams
from backend.participants import Participant, Role
from testbed.changes import take_in
from testbed.client import Event as Heard
from testbed.client import Phone, frame, start
from testbed.scenes import NO_PHONES_FRIEND as FRIEND
from testbed.scenes import NO_PHONES_LANDMARKS1 as STARTERS
from testbed.scenes import NO_PHONES_LANDMARKS2 as JOINERS

# The async tests run on asyncio, as the app does.
pytestmark = pytest.mark.anyio


@pytest.fixture
def anyio_backend() -> str:
    return "asyncio"


def streams_of(client: TestClient) -> EventStreams:
    streams: EventStreams = client.app.state.services.streams  # type: ignore[attr-defined]
    return streams


async def open_stream(
    client: TestClient, session_id: str, role: Role, last_event_id: int | None = None
) -> AsyncGenerator[str, None]:
    """One phone's stream, as the text that goes on the wire, frame by frame."""
    events = streams_of(client).events(Participant(session_id, role), last_event_id)
    # EventStreams.events is an async generator (aclose) that says AsyncIterator.
    async with aclosing(events):  # closing this closes the server's
        async for event in events:
            # As FastAPI writes it: data as written (raw_data), or serialised here.
            data = event.raw_data
            if data is None and event.data is not None:
                data = json.dumps(event.data)
            fields = event.model_dump(include={"event", "id", "retry", "comment"})
            yield format_sse_event(data_str=data, **fields).decode()


async def next_frames(stream: AsyncIterator[str], *types: str) -> list[Heard]:
    """Events until one of each ``types`` has arrived (pings skipped)."""
    frames, waiting = [], set(types)
    while waiting:
        chunk = await anext(stream)
        if chunk.startswith(":"):
            continue
        frames.append(frame(chunk))
        waiting.discard(frames[-1].type)
    return frames


async def joined_stream(
    client: TestClient, session_id: str, role: Role
) -> AsyncGenerator[str, None]:
    """One phone's stream, open: its retry line read, and its own presence heard."""
    stream = open_stream(client, session_id, role)
    await anext(stream)
    await next_frames(stream, "joined")
    return stream


async def test_changes_reach_the_other_phone_in_order(
    client: TestClient, starter: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    stream = open_stream(client, starter.session_id, "starter")
    assert (await anext(stream)).startswith("retry:")
    own = await next_frames(stream, "joined")  # its own presence
    joiner = joined(client, starter.state()["join_code"])
    frames = await next_frames(stream, "joined")
    assert frames[-1].data["role"] == "joiner"
    assert joiner.upload(temple_photos[1], "b.png").status_code == 200
    frames += await next_frames(stream, "photo")
    ids = [f.id for f in own + frames if f.id is not None]
    assert len(ids) == len(own + frames)  # every one stored, so resumable
    assert ids == sorted(ids)
    assert len(set(ids)) == len(ids)

    # A phone that reconnects with the last id it saw misses nothing.
    resumed = open_stream(client, starter.session_id, "starter", ids[0])
    await anext(resumed)
    replay = await next_frames(resumed, "photo")
    assert [f.id for f in replay] == ids[1:]
    await resumed.aclose()

    assert joiner.call("DELETE").status_code == 204
    last = await next_frames(stream, "expired")
    assert last[-1].type == "expired"
    with pytest.raises(StopAsyncIteration):
        await anext(stream)


async def test_a_phone_that_goes_away_is_shown_offline(
    client: TestClient, starter: Phone, joiner: Phone
) -> None:
    stream = await joined_stream(client, joiner.session_id, "joiner")
    assert starter.state()["participants"]["joiner"]["online"] is True
    await stream.aclose()  # the phone went: the server cancels its stream
    state = starter.state()
    assert state["participants"]["joiner"]["online"] is False
    watcher = open_stream(client, starter.session_id, "starter", 0)
    await anext(watcher)
    history = await next_frames(watcher, "left")
    assert history[-1].data["role"] == "joiner"
    await watcher.aclose()


async def test_listening_phones_stay_online_with_one_write_for_all(
    client: TestClient, starter: Phone, joiner: Phone, clock: FakeClock
) -> None:
    """The phones listening here are marked seen together (``keep_online``, every
    online_seconds / 3); a phone with a second stream open stays online when one closes."""
    streams = streams_of(client)
    online_for = client.app.state.settings.online_seconds  # type: ignore[attr-defined]
    first = await joined_stream(client, joiner.session_id, "joiner")
    second = await joined_stream(client, joiner.session_id, "joiner")
    writes: list[list[Participant]] = []
    seen_all = streams.presence.seen_all

    def seen_and_written(participants: Sequence[Participant], when: datetime) -> None:
        writes.append(list(participants))
        seen_all(participants, when)

    streams.presence.seen_all = seen_and_written  # type: ignore[method-assign]
    for _ in range(3):  # longer than online_seconds, kept online all along
        clock.advance(online_for / 3)
        streams.keep_online()
        assert starter.state()["participants"]["joiner"]["online"] is True
    assert writes == [[Participant(joiner.session_id, "joiner")]] * 3
    await first.aclose()  # one of its two streams ends
    assert starter.state()["participants"]["joiner"]["online"] is True
    await second.aclose()
    assert starter.state()["participants"]["joiner"]["online"] is False
    streams.keep_online()  # nobody listens here now: nothing to write
    assert len(writes) == 3


def test_the_watcher_sees_every_change_after_the_newest_events_were_deleted(
    client: TestClient, starter: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """Another process's changes reach this one's streams through the watcher, which
    remembers the newest event id it has looked at. Deleting the session with the newest
    events must not let later events take ids at or below it (SQLite reuses the ids after
    the largest left unless told not to)."""
    log = streams_of(client).log
    other, code = start(client)
    joined(client, code)  # the newer session's 'joined' is the newest event
    after, _ = log.changes_since(None, [])
    assert other.call("DELETE").status_code == 204
    assert starter.upload(temple_photos[0], "a.png").status_code == 200  # an event
    newest, sessions = log.changes_since(after, [other.session_id])
    assert newest > after
    assert sessions == {starter.session_id, other.session_id}  # changed; deleted


async def test_a_stream_ends_when_its_session_runs_out_of_time(
    client: TestClient, starter: Phone, clock: FakeClock
) -> None:
    stream = await joined_stream(client, starter.session_id, "starter")
    clock.advance(7200)
    rest = [chunk async for chunk in stream]
    assert frame(rest[-1]).type == "expired"


async def test_while_the_database_is_away_requests_get_503_and_streams_keep_pinging(
    client: TestClient,
    starter: Phone,
    joiner: Phone,
    temple_photos: tuple[bytes, bytes],
    database_outage: Callable[[], AbstractContextManager[None]],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    streams = streams_of(client)
    monkeypatch.setattr(streams, "keepalive_seconds", 0.2)  # it keeps trying to read
    monkeypatch.setattr(streams, "poll_seconds", 0.2)
    stream = await joined_stream(client, starter.session_id, "starter")

    with database_outage():
        for response in (
            starter.call("GET"),
            client.post("/api/sessions"),
            joiner.upload(temple_photos[1], "b.png"),
            client.get("/healthz"),
        ):
            assert response.status_code == 503, response.text
            assert response.json() == {"error": {"code": "database_unavailable", "message": ANY}}
        pings = [await anext(stream) for _ in range(5)]  # 1 s: the stream lives on
        assert pings == [": ping\n\n"] * 5

    deadline = time.monotonic() + 20
    while client.get("/healthz").status_code != 200:  # PostgreSQL: listening again too
        assert time.monotonic() < deadline, "the app did not recover"
        await anyio.sleep(0.1)
    assert joiner.upload(temple_photos[1], "b.png").status_code == 200
    frames = await next_frames(stream, "photo")
    assert frames[-1].data["role"] == "joiner"
    await stream.aclose()


def shown_after(state: dict[str, Any], events: list[Event]) -> dict[str, Any]:
    """The state a phone shows after taking in ``events`` as the app does, from the state it
    showed before; each must be taken in (none missing, none that cannot tell)."""
    for event in events:
        taken = take_in(state, event.type, event.data)
        assert taken is not None, f"the phone would fetch the state for {event}"
        state = taken
    return state


def test_each_change_carries_what_the_other_phone_shows(
    client: TestClient, starter: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """A phone that takes in the events of each change shows what reading the state would:
    the join, each photo, taps short of an answer, an answer that fails (said to each phone
    of its own photo), a curve, a point, and a photo replaced."""
    log = streams_of(client).log
    sid = starter.session_id
    phones = [starter]
    shown = {"starter": starter.state()}
    after = log.last_event_id(sid)

    def changed(change: Callable[[], Any]) -> None:
        nonlocal after
        change()
        events = log.events_after(sid, after)
        assert events, "the change has its events"
        after = events[-1].id
        for phone in phones:
            read = phone.state()
            assert shown_after(shown[phone.role], events) == read
            shown[phone.role] = read

    code = shown["starter"]["join_code"]
    answers: list[Any] = []
    changed(lambda: answers.append(client.post("/api/sessions/join", json={"code": code})))
    joiner = Phone(client, sid, answers[0].json()["token"], "joiner")
    phones.append(joiner)
    shown["joiner"] = joiner.state()
    changed(lambda: starter.upload(temple_photos[0], "a.png"))
    changed(lambda: joiner.upload(temple_photos[1], "b.png"))
    changed(lambda: starter.tap(landmarks=landmarks(STARTERS), friend=list(FRIEND)))
    changed(lambda: joiner.tap(landmarks=landmarks(JOINERS[:2])))  # short of an answer
    changed(lambda: joiner.tap(landmarks=landmarks(JOINERS[:3])))  # fails: said to each
    assert shown["joiner"]["answer_error"]["code"] == "degenerate_configuration"
    changed(lambda: joiner.tap(landmarks=landmarks(JOINERS[:4])))  # the curve
    assert shown["joiner"]["answer"]["method"] == "conic"
    s = scene(6)
    changed(lambda: starter.tap(landmarks=landmarks(s.landmarks1), friend=list(s.epipole1)))
    changed(lambda: joiner.tap(landmarks=landmarks(s.landmarks2)))  # a point
    assert shown["starter"]["answer"]["method"] == "pinhole_epipole"
    changed(lambda: joiner.upload(temple_photos[1], "c.png"))  # its taps go
    assert shown["starter"]["taps"]["joiner"] is None
