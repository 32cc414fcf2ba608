"""What the people of the load benchmark send (``benchmarks/searches.py``): the temple
photos as a phone shrinks them and the scenes their taps come from. Kept apart from Locust
(which patches the standard library with gevent on import), so that in-process measurements
(``benchmarks/search_cpu.py``) play the very same photos and taps.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import cv2
import numpy as np
from report import ROOT

from testbed.scenes import Scene, tap, temple_scene

TEMPLE = ROOT / "tests" / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")  # the starter's photo, the joiner's
LANDMARKS = 6
SCENES = 64  # temple scenes drawn up front; each search adds its own tap noise
TAP_SIGMA_PX = 2.0  # a finger's noise on the photo as sent


@dataclass(frozen=True)
class Crowd:
    """What the people send: two photos as a phone shrinks them, and the scenes their taps
    come from."""

    photos: tuple[bytes, bytes]
    scenes: list[Scene]
    side: int  # the photos' long side, px

    @staticmethod
    def made(side: int, seed: int) -> Crowd:
        """The temple views upscaled to ``side`` px (4:3) with sensor-like noise, as JPEG
        quality 90 (the phone app's): real edges and the weight of a photo."""
        rng = np.random.default_rng(seed)
        size = (side, side * 3 // 4)
        photos = []
        for name in PAIR:
            original = cv2.imread(str(TEMPLE / f"{name}.png"))
            if original is None:
                raise FileNotFoundError(TEMPLE / f"{name}.png")
            image = cv2.resize(original, size, interpolation=cv2.INTER_CUBIC)
            noisy = np.clip(image + rng.normal(0.0, 6.0, image.shape), 0, 255).astype(np.uint8)
            photos.append(cv2.imencode(".jpg", noisy, [cv2.IMWRITE_JPEG_QUALITY, 90])[1].tobytes())
        parameters = TEMPLE / "templeSR_par.txt"
        scenes = [temple_scene(parameters, *PAIR, LANDMARKS, rng) for _ in range(SCENES)]
        return Crowd((photos[0], photos[1]), scenes, side)

    def taps(
        self, rng: random.Random
    ) -> tuple[list[dict[str, float]], list[dict[str, float]], dict[str, float]]:
        """One search's taps in the photos' pixels: the starter's landmarks, the joiner's,
        and the starter's mark of the joiner."""
        scene = self.scenes[rng.randrange(len(self.scenes))]
        scale = self.side / scene.image_size1[0]
        noisy = tap(scene, TAP_SIGMA_PX / scale, np.random.default_rng(rng.randrange(2**32)))

        def marks(points: np.ndarray) -> list[dict[str, float]]:
            return [
                {"id": n, "x": round(float(x) * scale, 1), "y": round(float(y) * scale, 1)}
                | {"sigma": TAP_SIGMA_PX}
                for n, (x, y) in enumerate(points, start=1)
            ]

        x, y = (round(float(v) * scale, 1) for v in noisy.epipole1)
        mark = {"x": x, "y": y, "sigma": TAP_SIGMA_PX}
        return marks(noisy.landmarks1), marks(noisy.landmarks2), mark
