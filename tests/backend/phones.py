"""Test helpers for the service: the temple data, a controllable clock, one phone's API
(in-process, or over HTTP to a live server: a replica, or nginx in front of them), a
phone's event stream followed over HTTP."""

from __future__ import annotations

import json
import threading
import time
from dataclasses import dataclass
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import httpx
import numpy as np
from fastapi.testclient import TestClient

from testbed.scenes import Scene, Taps, tap, temple_scene

TEMPLE = Path(__file__).parents[1] / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")  # the seeker's photo, the buddy's


class FakeClock:
    """Time that moves only when told to."""

    def __init__(self) -> None:
        self.now = datetime(2026, 11, 21, 20, 0, 0)

    def __call__(self) -> datetime:
        return self.now

    def advance(self, seconds: float) -> None:
        self.now += timedelta(seconds=seconds)


@dataclass
class Phone:
    """One participant's side of the API."""

    client: TestClient
    session_id: str
    token: str
    role: str

    @property
    def auth(self) -> dict[str, str]:
        return {"Authorization": f"Bearer {self.token}"}

    def url(self, rest: str = "") -> str:
        return f"/api/sessions/{self.session_id}{rest}"

    def state(self) -> dict[str, Any]:
        response = self.client.get(self.url(), headers=self.auth)
        assert response.status_code == 200, response.text
        return response.json()

    def upload(self, photo: bytes, name: str = "photo.jpg") -> httpx.Response:
        return self.client.put(
            self.url("/photo"), headers=self.auth, files={"photo": (name, photo, "image/jpeg")}
        )

    def tap(self, **taps: Any) -> httpx.Response:
        return self.client.put(self.url("/taps"), headers=self.auth, json=taps)


class Listener(threading.Thread):
    """A phone's event stream over HTTP, collected in the background until 'expired'.

    ``last_event_id``: resume after it, as a reconnecting EventSource does.
    """

    def __init__(
        self, base: str, session_id: str, token: str, last_event_id: int | None = None
    ) -> None:
        super().__init__(daemon=True)
        self.url = f"{base}/api/sessions/{session_id}/events"
        self.token = token
        self.headers = {} if last_event_id is None else {"Last-Event-ID": str(last_event_id)}
        self.types: list[str] = []
        self.ids: list[int] = []
        self.data: list[dict[str, Any]] = []
        self.pings = 0
        self.ended = threading.Event()
        self.dropped = False

    def run(self) -> None:
        try:
            with httpx.stream(
                "GET", self.url, params={"token": self.token}, headers=self.headers, timeout=30
            ) as answer:
                assert answer.status_code == 200
                assert answer.headers["content-type"].startswith("text/event-stream")
                for line in answer.iter_lines():
                    if line.startswith("event: "):
                        self.types.append(line[7:])
                        if line == "event: expired":
                            break
                    elif line.startswith("id: "):
                        self.ids.append(int(line[4:]))
                    elif line.startswith("data: "):
                        self.data.append(json.loads(line[6:]))
                    elif line == ": ping":
                        self.pings += 1
        except httpx.TransportError:
            self.dropped = True  # the server went away (a phone's EventSource reconnects)
        self.ended.set()

    def count(self, type_: str, **data: Any) -> int:
        """How many ``type_`` events have arrived whose data has these items."""
        return sum(
            1
            for kind, body in zip(self.types, self.data, strict=False)
            if kind == type_ and data.items() <= body.items()
        )

    def wait_for(self, type_: str, count: int = 1, seconds: float = 15, **data: Any) -> None:
        """Until ``count`` such events have arrived; fails after ``seconds``."""
        deadline = time.monotonic() + seconds
        while self.count(type_, **data) < count:
            assert time.monotonic() < deadline, (
                f"no {type_} {data} event in {seconds} s; got {self.types}"
            )
            time.sleep(0.02)


@dataclass
class HttpPhone:
    """One phone over HTTP, talking to whatever ``base`` is: a replica, or nginx."""

    base: str
    session_id: str
    token: str

    @property
    def auth(self) -> dict[str, str]:
        return {"Authorization": f"Bearer {self.token}"}

    def url(self, rest: str = "") -> str:
        return f"{self.base}/api/sessions/{self.session_id}{rest}"

    def call(
        self, method: str, rest: str = "", headers: dict[str, str] | None = None, **options: Any
    ) -> httpx.Response:
        headers = self.auth | (headers or {})
        return httpx.request(method, self.url(rest), headers=headers, timeout=30, **options)

    def state(self) -> dict[str, Any]:
        answer = self.call("GET")
        assert answer.status_code == 200, answer.text
        return dict(answer.json())

    def upload(self, name: str) -> None:
        answer = self.call("PUT", "/photo", files=photo_form(name))
        assert answer.status_code == 200, answer.text

    def tap(self, **taps: Any) -> dict[str, Any]:
        answer = self.call("PUT", "/taps", json=taps)
        assert answer.status_code == 200, answer.text
        return dict(answer.json())

    def listen(self, last_event_id: int | None = None) -> Listener:
        listener = Listener(self.base, self.session_id, self.token, last_event_id)
        listener.start()
        return listener


def photo_form(name: str) -> dict[str, tuple[str, bytes, str]]:
    """The multipart form of a photo upload: a temple view by name."""
    return {"photo": (f"{name}.png", (TEMPLE / f"{name}.png").read_bytes(), "image/png")}


def pair(seeker_base: str, buddy_base: str) -> tuple[HttpPhone, HttpPhone]:
    """The seeker starts through one address, the buddy joins with the code through the
    other (the same one, through nginx)."""
    created = httpx.post(f"{seeker_base}/api/sessions", timeout=30).json()
    joined = httpx.post(
        f"{buddy_base}/api/sessions/join", json={"code": created["join_code"]}, timeout=30
    )
    assert joined.status_code == 200, joined.text
    sid = created["session_id"]
    return (
        HttpPhone(seeker_base, sid, created["token"]),
        HttpPhone(buddy_base, sid, joined.json()["token"]),
    )


def follow(seeker: HttpPhone, buddy: HttpPhone, seconds: float = 15) -> tuple[Listener, Listener]:
    """Both phones' event streams. The seeker's is open first (its own presence came back),
    so the buddy coming online is news to it: within ``seconds``, from wherever the buddy's
    stream is."""
    seeker_events = seeker.listen()
    seeker_events.wait_for("joined", role="seeker", online=True)
    buddy_events = buddy.listen()
    buddy_events.wait_for("joined", role="buddy", online=True)
    seeker_events.wait_for("joined", role="buddy", online=True, seconds=seconds)
    return seeker_events, buddy_events


def landmarks(points: np.ndarray) -> list[dict[str, float]]:
    """Taps in the API's form, numbered from 1 in order."""
    return [{"id": i + 1, "x": float(x), "y": float(y)} for i, (x, y) in enumerate(points)]


def scene_taps() -> tuple[Scene, Taps]:
    """Six landmarks of the temple PAIR and the buddy, tapped with 1 px of noise."""
    rng = np.random.default_rng(6)
    scene = temple_scene(TEMPLE / "templeSR_par.txt", *PAIR, 6, rng)
    return scene, tap(scene, 1.0, rng)
