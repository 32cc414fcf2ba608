"""Test helpers for the service: the temple data, a controllable clock, answers read. A
phone's calls and event stream are :mod:`testbed.client`'s (in-process, or over HTTP to a
live server: a replica, or nginx in front of them)."""

from __future__ import annotations

import math
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import numpy as np

from testbed.client import Listener, Phone
from testbed.scenes import Scene, Taps, tap, temple_scene

TEMPLE = Path(__file__).parents[1] / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")  # the starter's photo, the joiner's

# Streams read the event table only when woken or every 30 s, and ping every 20 s: an
# event that reaches the other replica's stream within CROSSING_SECONDS was carried by
# LISTEN/NOTIFY, nothing else.
REPLICA_ENV = {"BUDDY_EVENT_POLL_SECONDS": "30", "BUDDY_KEEPALIVE_SECONDS": "20"}
CROSSING_SECONDS = 2.0


class FakeClock:
    """Time that moves only when told to."""

    def __init__(self) -> None:
        self.now = datetime(2026, 11, 21, 20, 0, 0)

    def __call__(self) -> datetime:
        return self.now

    def advance(self, seconds: float) -> None:
        self.now += timedelta(seconds=seconds)


def in_region(region: dict[str, Any], point: Any) -> bool:
    """Whether ``point`` (x, y) lies in an answer's 95 % ellipse."""
    (cx, cy), (a, b) = region["center"], region["axes"]
    angle = math.radians(region["angle_deg"])
    dx, dy = point[0] - cx, point[1] - cy
    u = dx * math.cos(angle) + dy * math.sin(angle)
    v = -dx * math.sin(angle) + dy * math.cos(angle)
    return (u / a) ** 2 + (v / b) ** 2 <= 1.0


def landmarks(
    points: Any, ids: list[int] | None = None, sigma: float | None = None
) -> list[dict[str, float]]:
    """Landmarks as a phone sends them, numbered from 1 (or ``ids``), each tap with its
    precision (px) if ``sigma`` is given."""
    ids = ids or list(range(1, len(points) + 1))
    taps = [{"id": i, "x": float(x), "y": float(y)} for i, (x, y) in zip(ids, points, strict=True)]
    return taps if sigma is None else [tap | {"sigma": sigma} for tap in taps]


def temple_pair(count: int, rng: np.random.Generator) -> Scene:
    """``count`` landmarks of the temple PAIR, the starter and the joiner in each other's photo."""
    return temple_scene(TEMPLE / "templeSR_par.txt", *PAIR, count, rng)


def scene(landmarks: int, seed: int = 0) -> Scene:
    """``landmarks`` of the temple PAIR drawn from ``seed``."""
    return temple_pair(landmarks, np.random.default_rng(seed))


def scene_taps() -> tuple[Scene, Taps]:
    """Six landmarks of the temple PAIR and the joiner, tapped with 1 px of noise."""
    rng = np.random.default_rng(6)
    scene = temple_pair(6, rng)
    return scene, tap(scene, 1.0, rng)


Phones = tuple[Phone, Phone]  # the starter's and the joiner's


def photos_uploaded(starter: Phone, joiner: Phone, photos: tuple[bytes, bytes]) -> None:
    """Each phone uploads its photo of ``photos`` (640 x 480, no lens told)."""
    for phone, photo in zip((starter, joiner), photos, strict=True):
        stored = phone.upload(photo, "photo.png")
        assert stored.status_code == 200, stored.text
        assert stored.json() == stored_photo(640, 480)


def stored_photo(width: int, height: int) -> dict[str, Any]:
    """What the service says of a photo it stored upright at ``width`` x ``height`` px, sent
    with no lens and no sensor readings (PUT /photo's answer, the state's ``photos``)."""
    return {
        "width": width,
        "height": height,
        "scale": 1.0,
        "lens": None,
        "gravity": None,
        "heading": None,
        "heading_sigma_deg": None,
    }


def error_of(response: Any, status: int | None = None) -> str:
    """The code of a refusal in the one shape: a code and a sentence, and for the solver's
    refusals the reason and its parameters (nothing else); its status, if given, checked."""
    if status is not None:
        assert response.status_code == status, response.text
    body = response.json()
    assert set(body) == {"error"}, body
    fields = set(body["error"])
    assert {"code", "message"} <= fields, body
    assert fields == {"code", "message"} or "reason" in fields, body
    assert body["error"]["message"].endswith("."), body
    return str(body["error"]["code"])


def end(phone: Phone, *streams: Listener) -> None:
    """Delete now: every stream of the session ends (and the replicas stop promptly)."""
    assert phone.call("DELETE").status_code == 204
    for stream in streams:
        assert stream.ended.wait(CROSSING_SECONDS)
        assert stream.types[-1] == "expired"
