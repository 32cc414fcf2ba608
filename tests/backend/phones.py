"""Test helpers for the service: the temple data, a controllable clock, one phone's API
(in-process, or over HTTP to a live server: a replica, or nginx in front of them), a
phone's event stream followed over HTTP."""

from __future__ import annotations

import json
import math
import threading
import time
from dataclasses import dataclass
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import httpx2
import numpy as np
from fastapi.testclient import TestClient

from testbed.scenes import Scene, Taps, tap, temple_scene

TEMPLE = Path(__file__).parents[1] / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")  # the starter's photo, the joiner's


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

    def upload(self, photo: bytes, name: str = "photo.jpg") -> httpx2.Response:
        return self.client.put(
            self.url("/photo"), headers=self.auth, files={"photo": (name, photo, "image/jpeg")}
        )

    def tap(self, **taps: Any) -> httpx2.Response:
        """PUT these taps; a ``friend`` given as ``(x, y)`` is sent as ``{"x", "y"}``."""
        friend = taps.get("friend")
        if isinstance(friend, list | tuple):
            taps["friend"] = {"x": friend[0], "y": friend[1]}
        return self.client.put(self.url("/taps"), headers=self.auth, json=taps)


def in_region(region: dict[str, Any], point: Any) -> bool:
    """Whether ``point`` (x, y) lies in an answer's 95 % ellipse."""
    (cx, cy), (a, b) = region["center"], region["axes"]
    angle = math.radians(region["angle_deg"])
    dx, dy = point[0] - cx, point[1] - cy
    u = dx * math.cos(angle) + dy * math.sin(angle)
    v = -dx * math.sin(angle) + dy * math.cos(angle)
    return (u / a) ** 2 + (v / b) ** 2 <= 1.0


def mark(point: Any) -> dict[str, float]:
    """A friend mark at ``point`` (x, y), as the API takes it."""
    return {"x": float(point[0]), "y": float(point[1])}


def friend_in(state: dict[str, Any], role: str) -> list[float] | None:
    """Where the answer puts ``role``'s friend in ``role``'s photo."""
    answer = state["answer"]
    return None if answer is None else answer["in_photo"][role]["friend"]


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
            with httpx2.stream(
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
        except httpx2.TransportError:
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
    ) -> httpx2.Response:
        headers = self.auth | (headers or {})
        return httpx2.request(method, self.url(rest), headers=headers, timeout=30, **options)

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


def pair(starter_base: str, joiner_base: str) -> tuple[HttpPhone, HttpPhone]:
    """The starter starts through one address, the joiner joins with the code through the
    other (the same one, through nginx)."""
    created = httpx2.post(f"{starter_base}/api/sessions", timeout=30).json()
    joined = httpx2.post(
        f"{joiner_base}/api/sessions/join", json={"code": created["join_code"]}, timeout=30
    )
    assert joined.status_code == 200, joined.text
    sid = created["session_id"]
    return (
        HttpPhone(starter_base, sid, created["token"]),
        HttpPhone(joiner_base, sid, joined.json()["token"]),
    )


def follow(starter: HttpPhone, joiner: HttpPhone, seconds: float = 15) -> tuple[Listener, Listener]:
    """Both phones' event streams. The starter's is open first (its own presence came
    back), so the joiner coming online is news to it: within ``seconds``, from wherever the
    joiner's stream is."""
    starter_events = starter.listen()
    starter_events.wait_for("joined", role="starter", online=True)
    joiner_events = joiner.listen()
    joiner_events.wait_for("joined", role="joiner", online=True)
    starter_events.wait_for("joined", role="joiner", online=True, seconds=seconds)
    return starter_events, joiner_events


def landmarks(points: np.ndarray) -> list[dict[str, float]]:
    """Landmarks as a phone sends them, numbered from 1, each tap with its precision (px)."""
    return [
        {"id": i + 1, "x": float(x), "y": float(y), "sigma": 2.0} for i, (x, y) in enumerate(points)
    ]


def scene_taps() -> tuple[Scene, Taps]:
    """Six landmarks of the temple PAIR and the joiner, tapped with 1 px of noise."""
    rng = np.random.default_rng(6)
    scene = temple_scene(TEMPLE / "templeSR_par.txt", *PAIR, 6, rng)
    return scene, tap(scene, 1.0, rng)
