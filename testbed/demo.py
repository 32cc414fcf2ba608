"""The solver on the real temple photos: ``python -m testbed.demo [--out DIR]`` (``make demo``).

Two calibrated Middlebury temple views that face each other (templeSR0003 / templeSR0006)
stand in for the two phones: landmarks are drawn inside the model's bounding box, projected
with both real cameras, and tapped with 1 px noise, friend 2 too. Prints the answer as the
REST API will return it, how far it is from the truth, and writes both phones' overlays.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import cv2
import numpy as np

from shared_solver import draw_overlay

from .scenes import solved, tap, temple_scene

TEMPLE = Path(__file__).resolve().parents[1] / "tests" / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("var/demo"), help="overlay folder")
    parser.add_argument("--landmarks", type=int, default=6)
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--data", type=Path, default=TEMPLE, help="temple photos + calibration")
    args = parser.parse_args()

    rng = np.random.default_rng(args.seed)
    scene = temple_scene(args.data / "templeSR_par.txt", *PAIR, args.landmarks, rng)
    taps = tap(scene, 1.0, rng)
    result = solved(scene, taps, tap_sigma=1.0)
    print(json.dumps(result.model_dump(mode="json"), indent=2))
    if result.epipole2 is not None:
        error = np.linalg.norm(np.array(result.epipole2) - scene.epipole2)
        print(
            f"\nthe friend really is at {scene.epipole2.round(1).tolist()}, off by {error:.1f} px"
        )

    args.out.mkdir(parents=True, exist_ok=True)
    for number, name, points in ((1, PAIR[0], taps.landmarks1), (2, PAIR[1], taps.landmarks2)):
        image = cv2.imread(str(args.data / f"{name}.png"))
        drawn = draw_overlay(image, result, photo=number, points=points)  # type: ignore[arg-type]
        path = args.out / f"photo{number}.png"
        cv2.imwrite(str(path), drawn)
        print(f"photo {number}'s phone: {path}")


if __name__ == "__main__":
    main()
