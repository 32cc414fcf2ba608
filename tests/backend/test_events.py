"""The event stream: each change reaches the other phone, with ids to resume from."""

from __future__ import annotations

import time
from collections.abc import AsyncIterator, Callable
from contextlib import AbstractContextManager

import anyio
import pytest
from fastapi.testclient import TestClient
from phones import FakeClock, Phone

from backend.storage.repository import Participant


@pytest.fixture
def anyio_backend() -> str:
    return "asyncio"


async def connected() -> bool:
    return False


async def next_frames(stream: AsyncIterator[str], *types: str) -> list[str]:
    """Frames until one of each ``types`` has arrived (pings skipped)."""
    frames, waiting = [], set(types)
    while waiting:
        chunk = await anext(stream)
        if chunk.startswith(":"):
            continue
        frames.append(chunk)
        waiting.discard(_type(chunk))
    return frames


def _type(chunk: str) -> str:
    return next((line[7:] for line in chunk.splitlines() if line.startswith("event: ")), "")


def _id(chunk: str) -> int:
    return int(next(line[4:] for line in chunk.splitlines() if line.startswith("id: ")))


@pytest.mark.anyio
async def test_changes_reach_the_other_phone_in_order(
    client: TestClient, seeker: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    service = client.app.state.service  # type: ignore[attr-defined]
    stream = service.events(Participant(seeker.session_id, "seeker"), None, connected)
    assert (await anext(stream)).startswith("retry:")
    joined = await next_frames(stream, "joined")  # its own presence
    code = seeker.state()["join_code"]
    buddy_token = client.post("/api/sessions/join", json={"code": code}).json()["token"]
    buddy = Phone(client, seeker.session_id, buddy_token, "buddy")
    frames = await next_frames(stream, "joined")
    assert '"role": "buddy"' in frames[-1]
    assert buddy.upload(temple_photos[1], "b.png").status_code == 200
    frames += await next_frames(stream, "photo")
    ids = [_id(f) for f in joined + frames]
    assert ids == sorted(ids)
    assert len(set(ids)) == len(ids)

    # A phone that reconnects with the last id it saw misses nothing.
    resumed = service.events(Participant(seeker.session_id, "seeker"), ids[0], connected)
    await anext(resumed)
    replay = await next_frames(resumed, "photo")
    assert [_id(f) for f in replay] == ids[1:]
    await resumed.aclose()

    assert client.delete(buddy.url(), headers=buddy.auth).status_code == 204
    last = await next_frames(stream, "expired")
    assert _type(last[-1]) == "expired"
    with pytest.raises(StopAsyncIteration):
        await anext(stream)


@pytest.mark.anyio
async def test_a_phone_that_goes_away_is_shown_offline(
    client: TestClient, seeker: Phone, buddy: Phone
) -> None:
    service = client.app.state.service  # type: ignore[attr-defined]
    gone = False

    async def disconnected() -> bool:
        return gone

    stream = service.events(Participant(buddy.session_id, "buddy"), None, disconnected)
    await anext(stream)
    await next_frames(stream, "joined")
    assert seeker.state()["participants"]["buddy"]["online"] is True
    gone = True
    rest = [chunk async for chunk in stream]  # the stream ends by itself
    assert all(chunk.startswith(":") or "event: " in chunk for chunk in rest)
    state = seeker.state()
    assert state["participants"]["buddy"]["online"] is False
    watcher = service.events(Participant(seeker.session_id, "seeker"), 0, connected)
    await anext(watcher)
    history = await next_frames(watcher, "left")
    assert '"role": "buddy"' in history[-1]
    await watcher.aclose()


@pytest.mark.anyio
async def test_listening_phones_stay_online_with_one_write_for_all(
    client: TestClient, seeker: Phone, buddy: Phone, clock: FakeClock
) -> None:
    """The phones listening here are marked seen together (``keep_online``, every
    online_seconds / 3); a phone with a second stream open stays online when one closes."""
    service = client.app.state.service  # type: ignore[attr-defined]
    online_for = service.settings.online_seconds
    closed = False

    async def first_closed() -> bool:
        return closed

    first = service.events(Participant(buddy.session_id, "buddy"), None, first_closed)
    second = service.events(Participant(buddy.session_id, "buddy"), None, connected)
    for stream in (first, second):
        await anext(stream)
        await next_frames(stream, "joined")
    writes = []
    seen_all = service.store.seen_all
    service.store.seen_all = lambda who, when: (writes.append(list(who)), seen_all(who, when))
    for _ in range(3):  # longer than online_seconds, kept online all along
        clock.advance(online_for / 3)
        service.keep_online()
        assert seeker.state()["participants"]["buddy"]["online"] is True
    assert writes == [[Participant(buddy.session_id, "buddy")]] * 3
    closed = True
    _ = [chunk async for chunk in first]  # one of its two streams ends
    assert seeker.state()["participants"]["buddy"]["online"] is True
    await second.aclose()
    assert seeker.state()["participants"]["buddy"]["online"] is False
    service.keep_online()  # nobody listens here now: nothing to write
    assert len(writes) == 3


def test_the_watcher_sees_every_change_after_the_newest_events_were_deleted(
    client: TestClient, seeker: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """Another process's changes reach this one's streams through the watcher, which
    remembers the newest event id it has looked at. Deleting the session with the newest
    events must not let later events take ids at or below it (SQLite reuses the ids after
    the largest left unless told not to)."""
    store = client.app.state.service.store  # type: ignore[attr-defined]
    newer = client.post("/api/sessions").json()
    joined = client.post("/api/sessions/join", json={"code": newer["join_code"]})
    assert joined.status_code == 200  # the newer session's 'joined' is the newest event
    other = Phone(client, newer["session_id"], newer["token"], "seeker")
    after, _ = store.changes_since(None, [])
    assert client.delete(other.url(), headers=other.auth).status_code == 204
    assert seeker.upload(temple_photos[0], "a.png").status_code == 200  # an event
    newest, sessions = store.changes_since(after, [other.session_id])
    assert newest > after
    assert sessions == {seeker.session_id, other.session_id}  # changed; deleted


@pytest.mark.anyio
async def test_a_stream_ends_when_its_session_runs_out_of_time(
    client: TestClient, seeker: Phone, clock: FakeClock
) -> None:
    service = client.app.state.service  # type: ignore[attr-defined]
    stream = service.events(Participant(seeker.session_id, "seeker"), None, connected)
    await anext(stream)
    await next_frames(stream, "joined")
    clock.advance(7200)
    rest = [chunk async for chunk in stream]
    assert _type(rest[-1]) == "expired"


@pytest.mark.anyio
async def test_while_the_database_is_away_requests_get_503_and_streams_keep_pinging(
    client: TestClient,
    seeker: Phone,
    buddy: Phone,
    temple_photos: tuple[bytes, bytes],
    database_outage: Callable[[], AbstractContextManager[None]],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    service = client.app.state.service  # type: ignore[attr-defined]
    quick = {"keepalive_seconds": 0.2, "event_poll_seconds": 0.2}  # it keeps trying to read
    monkeypatch.setattr(service, "settings", service.settings.model_copy(update=quick))
    stream = service.events(Participant(seeker.session_id, "seeker"), None, connected)
    await anext(stream)
    await next_frames(stream, "joined")

    with database_outage():
        for response in (
            client.get(seeker.url(), headers=seeker.auth),
            client.post("/api/sessions"),
            buddy.upload(temple_photos[1], "b.png"),
            client.get("/healthz"),
        ):
            assert response.status_code == 503, response.text
            assert response.json() == {
                "error": {
                    "code": "database_unavailable",
                    "message": response.json()["error"]["message"],
                }
            }
        pings = [await anext(stream) for _ in range(5)]  # 1 s: the stream lives on
        assert pings == [": ping\n\n"] * 5

    deadline = time.monotonic() + 20
    while client.get("/healthz").status_code != 200:  # PostgreSQL: listening again too
        assert time.monotonic() < deadline, "the app did not recover"
        await anyio.sleep(0.1)
    assert buddy.upload(temple_photos[1], "b.png").status_code == 200
    frames = await next_frames(stream, "photo")
    assert '"role": "buddy"' in frames[-1]
    await stream.aclose()
