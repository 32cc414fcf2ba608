"""Test helpers for the service: the temple data, a controllable clock, answers read. A
phone's calls and event stream are :mod:`testbed.client`'s (in-process, or over HTTP to a
live server: a replica, or nginx in front of them)."""

from __future__ import annotations

from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import cv2
import httpx2
import numpy as np

from testbed.browser.play import inside
from testbed.client import Listener, Phone, follow, live, pair
from testbed.scenes import Scene, Taps, tap, temple_scene

TEMPLE = Path(__file__).parents[1] / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")  # the starter's photo, the joiner's
# Their PNG files' bytes, as the phones upload them (640 x 480).
TEMPLE_PHOTOS = ((TEMPLE / f"{PAIR[0]}.png").read_bytes(), (TEMPLE / f"{PAIR[1]}.png").read_bytes())

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
    """Whether ``point`` (x, y) lies in an answer's 95 % ellipse (as the browser tests read
    the phone's)."""
    ellipse = (*region["axes"], region["angle_deg"])
    return inside(np.asarray(point), np.asarray(region["center"]), ellipse)


def landmarks(
    points: Any, ids: list[int] | None = None, sigma: float | None = None
) -> list[dict[str, float]]:
    """Landmarks as a phone sends them, numbered from 1 (or ``ids``), each tap with its
    precision (px) if ``sigma`` is given."""
    ids = ids or list(range(1, len(points) + 1))
    taps = [{"id": i, "x": float(x), "y": float(y)} for i, (x, y) in zip(ids, points, strict=True)]
    return taps if sigma is None else [tap | {"sigma": sigma} for tap in taps]


def scene(landmarks: int, seed: int | np.random.Generator = 0) -> Scene:
    """``landmarks`` of the temple PAIR, the starter and the joiner in each other's photo,
    drawn from ``seed`` (or from a generator, which goes on)."""
    rng = np.random.default_rng(seed)
    return temple_scene(TEMPLE / "templeSR_par.txt", *PAIR, landmarks, rng)


def scene_taps() -> tuple[Scene, Taps]:
    """Six landmarks of the temple PAIR and the joiner, tapped with 1 px of noise."""
    rng = np.random.default_rng(6)
    drawn = scene(6, rng)
    return drawn, tap(drawn, 1.0, rng)


Phones = tuple[Phone, Phone]  # the starter's and the joiner's


def joined(client: httpx2.Client, code: str) -> Phone:
    """The joiner's calls, once it has joined with ``code`` (failing unless it may)."""
    answer = client.post("/api/sessions/join", json={"code": code})
    assert answer.status_code == 200, answer.text
    body = answer.json()
    return Phone(client, body["session_id"], body["token"], "joiner")


def tapped_scene(starter: Phone, joiner: Phone, s: Scene, count: int | None = None) -> Any:
    """The starter taps ``s``'s landmarks and marks the joiner; the joiner taps the first
    ``count`` landmarks (all unless told): the state the joiner's taps answered."""
    starter.tapped(landmarks=landmarks(s.landmarks1), friend=s.epipole1)
    return joiner.tapped(landmarks=landmarks(s.landmarks2[:count]))


def image_of(answer: httpx2.Response, flags: int = cv2.IMREAD_COLOR) -> np.ndarray:
    """The picture of a 200 answer, decoded by OpenCV ((H, W, 3) BGR unless ``flags`` say)."""
    assert answer.status_code == 200, answer.text
    image = cv2.imdecode(np.frombuffer(answer.content, np.uint8), flags)
    assert image is not None
    return image


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


Followed = tuple[Phone, Phone, Listener, Listener]  # the phones, then their streams


def followed(starter_url: str, joiner_url: str | None = None) -> Followed:
    """A search started on the server at ``starter_url`` and joined on ``joiner_url`` (the
    same by default), both streams open (:func:`testbed.client.follow`)."""
    starter, joiner = pair(live(starter_url), live(joiner_url or starter_url))
    return starter, joiner, *follow(starter, joiner, CROSSING_SECONDS)


def photos_and_taps_cross(
    starter: Phone,
    joiner: Phone,
    starter_events: Listener,
    joiner_events: Listener,
    seconds: float = CROSSING_SECONDS,
) -> tuple[Scene, dict[str, Any]]:
    """Both temple photos (each stored as it came) and both tap sets (:func:`scene_taps`):
    each change reaches the other phone's stream within ``seconds``, whatever process each
    phone is on. The scene, and the joiner's state with the answer (computed in the joiner's
    process)."""
    assert starter.uploaded(TEMPLE / f"{PAIR[0]}.png") == stored_photo(640, 480)
    joiner_events.wait_for("photo", role="starter", seconds=seconds)
    assert joiner.uploaded(TEMPLE / f"{PAIR[1]}.png") == stored_photo(640, 480)
    starter_events.wait_for("photo", role="joiner", seconds=seconds)
    scene, taps = scene_taps()
    starter.tapped(landmarks=landmarks(taps.landmarks1, sigma=2.0), friend=taps.epipole1)
    joiner_events.wait_for("taps", role="starter", seconds=seconds)
    state = joiner.tapped(landmarks=landmarks(taps.landmarks2, sigma=2.0))
    starter_events.wait_for("taps", role="joiner", seconds=seconds)
    starter_events.wait_for("answer", version=state["version"], seconds=seconds)
    return scene, state


def kept(phone: Phone) -> tuple[dict[str, Any], list[bytes]]:
    """What no failure may lose: the state's photos, taps and version; both photos' bytes."""
    state = phone.state()
    photos = [phone.call("GET", f"/photo/{role}").content for role in ("starter", "joiner")]
    return {key: state[key] for key in ("photos", "taps", "version")}, photos


def joiner_tapping(
    starter: Phone, joiner: Phone, starter_events: Listener
) -> tuple[Scene, Taps, tuple[dict[str, Any], list[bytes]]]:
    """Both temple photos up, the starter's taps in (:func:`scene_taps`, the friend marked),
    the joiner still tapping (3 landmarks), heard by the starter's stream: the scene, the
    taps, and what the session has :func:`kept`."""
    starter.uploaded(TEMPLE / f"{PAIR[0]}.png")
    joiner.uploaded(TEMPLE / f"{PAIR[1]}.png")
    scene, taps = scene_taps()
    starter.tapped(landmarks=landmarks(taps.landmarks1, sigma=2.0), friend=taps.epipole1)
    joiner.tapped(landmarks=landmarks(taps.landmarks2[:3], sigma=2.0))
    starter_events.wait_for("taps", role="joiner", seconds=CROSSING_SECONDS)
    return scene, taps, kept(starter)


def end(phone: Phone, *streams: Listener, seconds: float = CROSSING_SECONDS) -> None:
    """Delete now: every stream of the session ends within ``seconds`` (and the replicas
    stop promptly)."""
    assert phone.call("DELETE").status_code == 204
    for stream in streams:
        assert stream.ended.wait(seconds)
        assert stream.types[-1] == "expired"
