"""Test helpers for the service: the temple data, a controllable clock, answers read. A
phone's calls and event stream are :mod:`testbed.client`'s (in-process, or over HTTP to a
live server: a replica, or nginx in front of them)."""

from __future__ import annotations

import math
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import numpy as np

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
