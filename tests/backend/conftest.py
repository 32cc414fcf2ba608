"""Fixtures for the service: an app on a fresh SQLite file, a controllable clock, and two
phones already paired."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient
from phones import TEMPLE, FakeClock, Phone

from backend.main import create_app
from backend.settings import Settings


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def settings(tmp_path: Path) -> Settings:
    return Settings(database_url=f"sqlite:///{tmp_path / 'buddy.db'}", sweep_interval_seconds=3600)


@pytest.fixture
def app(settings: Settings, clock: FakeClock) -> FastAPI:
    return create_app(settings, clock)


@pytest.fixture
def client(app: FastAPI) -> Iterator[TestClient]:
    with TestClient(app, raise_server_exceptions=False) as test_client:
        yield test_client


@pytest.fixture
def seeker(client: TestClient) -> Phone:
    created = client.post("/api/sessions")
    assert created.status_code == 201, created.text
    body = created.json()
    return Phone(client, body["session_id"], body["token"], "seeker")


@pytest.fixture
def buddy(client: TestClient, seeker: Phone) -> Phone:
    code = seeker.state()["join_code"]
    joined = client.post("/api/sessions/join", json={"code": code})
    assert joined.status_code == 200, joined.text
    body = joined.json()
    return Phone(client, body["session_id"], body["token"], "buddy")


@pytest.fixture
def temple_photos() -> tuple[bytes, bytes]:
    """The facing temple pair as uploaded by the two phones (PNG, 640x480)."""
    return (TEMPLE / "templeSR0003.png").read_bytes(), (TEMPLE / "templeSR0006.png").read_bytes()
