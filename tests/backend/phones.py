"""Test helpers for the service: the temple data, a controllable clock, one phone's API,
a phone's event stream followed over HTTP."""

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
from fastapi.testclient import TestClient

TEMPLE = Path(__file__).parents[1] / "data" / "temple"


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
