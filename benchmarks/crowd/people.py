"""The people of the sessions and what their phones send: their pauses, the photos, the
taps."""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from report import ROOT

from testbed.scenes import Scene, tap, temple_scene

TEMPLE = ROOT / "tests" / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")  # the seeker's photo, the buddy's

# A person's pauses, seconds, uniform in each range (``--speed`` divides them): the buddy
# scans the QR code or types the code; each takes a photo; the seeker picks a landmark and
# places it with the loupe; the buddy finds the seeker's landmark #n in their own photo from
# its crop; both read the answer before "Delete now". A session then lasts about 1.5 min.
PAUSES = {
    "join": (5.0, 15.0),
    "photo": (5.0, 15.0),
    "tap": (3.0, 8.0),
    "find": (5.0, 15.0),
    "read": (3.0, 10.0),
}

LANDMARKS = 6
PHOTO_SIZE = (1600, 1200)  # a phone's shrunk photo: the temple views upscaled 2.5x
PHOTO_QUALITY = 92
PHOTO_NOISE_SIGMA = 6.0  # grey levels: sensor noise, so the JPEG weighs what a photo does
TAP_SIGMA_PX = 2.0  # a finger's noise on the 1600x1200 photo
SCENES = 64  # temple scenes drawn up front; each session adds its own tap noise


def phone_photo(name: str, rng: np.random.Generator) -> bytes:
    """A temple view upscaled to 1600x1200 (bicubic) with Gaussian sensor-like noise, as
    the JPEG a phone sends after shrinking its photo: real edges, a realistic weight."""
    image = cv2.imread(str(TEMPLE / f"{name}.png"), cv2.IMREAD_COLOR)
    if image is None:
        raise FileNotFoundError(TEMPLE / f"{name}.png")
    large = cv2.resize(image, PHOTO_SIZE, interpolation=cv2.INTER_CUBIC).astype(np.float32)
    noisy = np.clip(large + rng.normal(0.0, PHOTO_NOISE_SIGMA, large.shape), 0, 255)
    ok, data = cv2.imencode(
        ".jpg", noisy.astype(np.uint8), [cv2.IMWRITE_JPEG_QUALITY, PHOTO_QUALITY]
    )
    if not ok:
        raise RuntimeError("OpenCV could not encode the photo")
    return bytes(data.tobytes())


def temple_scenes(rng: np.random.Generator) -> list[Scene]:
    """Landmarks drawn on the temple, seen by the calibrated cameras of the two photos."""
    parameters = TEMPLE / "templeSR_par.txt"
    return [temple_scene(parameters, *PAIR, LANDMARKS, rng) for _ in range(SCENES)]


@dataclass(frozen=True)
class SessionTaps:
    """What both people tap in one session, in the 1600x1200 photos' pixels."""

    seeker: list[dict[str, float]]  # landmarks #1..#6
    buddy: list[dict[str, float]]
    buddy_mark: dict[str, float]  # the joiner, marked in the starter's photo


def session_taps(scene: Scene, rng: np.random.Generator) -> SessionTaps:
    scale = PHOTO_SIZE[0] / scene.image_size1[0]  # the temple views are 640x480
    noisy = tap(scene, TAP_SIGMA_PX / scale, rng)

    def marks(points: np.ndarray) -> list[dict[str, float]]:
        inside = np.clip(points * scale, 0, PHOTO_SIZE)
        return [
            {"id": n, "x": round(float(x), 1), "y": round(float(y), 1)}
            for n, (x, y) in enumerate(inside, start=1)
        ]

    buddy_mark = np.clip(noisy.epipole1 * scale, 0, PHOTO_SIZE)
    return SessionTaps(
        marks(noisy.landmarks1),
        marks(noisy.landmarks2),
        {"x": round(float(buddy_mark[0]), 1), "y": round(float(buddy_mark[1]), 1)},
    )
