"""Test helpers for the service: the temple data, a controllable clock, one phone's API."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import httpx
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

    def upload(self, photo: bytes, name: str = "photo.jpg") -> httpx.Response:
        return self.client.put(
            self.url("/photo"), headers=self.auth, files={"photo": (name, photo, "image/jpeg")}
        )

    def tap(self, **taps: Any) -> httpx.Response:
        return self.client.put(self.url("/taps"), headers=self.auth, json=taps)
