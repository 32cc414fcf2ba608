"""Derive ``tests/data/real_cameras/`` from the public source data (run it where the source
files are; the suite itself only reads the JSON it writes).

    .venv/bin/python -m testbed.real_cameras_build --meva DIR --gopro DIR [--out DIR]

* ``--meva``: the MEVA March 2018 camera models, ``metadata/camera-models/old/2018-03/`` of
  the MEVA data repository (https://gitlab.kitware.com/meva/meva-data-repo; a copy is on
  GitHub as ``KeivanShariatmadar/meva-data``): ``cameras/*.krtd``, ``landmarks.ply``,
  ``tracks.txt``, ``frames.txt`` and ``frames/*.png``. Kitware and IARPA, CC BY 4.0. The
  landmarks are the 3-D points Kitware's annotators clicked in the frames to calibrate the
  cameras; their clicks are kept (lens corrected) where they agree with the calibration.
* ``--gopro``: the four EPFL GoPro frames and their calibration as shipped in the
  ``lcit/pypom`` repository (``examples/full_example/``, GPL-3.0): ``frame_gopro6.N.jpg``,
  ``calibration/{intrinsics,extrinsics}_gopro6.N.json``. The landmarks are the crossings of
  the tape on the hall's floor and points picked by hand on fixtures
  (``epfl_gopro_rig_landmarks.json`` in the output directory), measured in the photos by
  ``testbed/real_cameras_gopro.py``.

Every landmark is written in the undistorted pixel frame (``cv2.undistortPoints(..., P=K)``)
and kept only within ``--max-sampson`` px (Sampson distance) of the true geometry and in front
of both cameras. ``testbed.real_cameras`` reads the result.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import re
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from testbed.real_cameras import (
    DATA,
    Landmark,
    RealPair,
    SourceCamera,
    camera_focal_35mm,
    reversed_pair,
)
from testbed.real_cameras_gopro import gopro
from testbed.real_cameras_meva import meva
from testbed.scenes import inside

MAX_SAMPSON_PX = 2.0
# A pair is kept with at least this many landmarks (3 answer with a phone camera; 6 leave
# room to draw different subsets).
MIN_LANDMARKS = 6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--meva", type=Path, help="MEVA's camera-models/old/2018-03 directory")
    parser.add_argument("--gopro", type=Path, help="the EPFL GoPro frames and calibration")
    parser.add_argument(
        "--gopro-landmarks",
        type=Path,
        default=DATA / "epfl_gopro_rig_landmarks.json",
        help="where to measure the rig's landmarks",
    )
    parser.add_argument("--out", type=Path, default=DATA)
    parser.add_argument("--max-sampson", type=float, default=MAX_SAMPSON_PX)
    args = parser.parse_args()
    if args.meva is not None:
        cameras, landmarks = meva(args.meva)
        write(args.out / "meva_2018_03.json", MEVA_SOURCE, cameras, landmarks, args.max_sampson)
    if args.gopro is not None:
        cameras, landmarks = gopro(args.gopro, args.gopro_landmarks)
        write(args.out / "epfl_gopro_rig.json", GOPRO_SOURCE, cameras, landmarks, args.max_sampson)


MEVA_SOURCE = {
    "title": "MEVA (Multiview Extended Video with Activities), March 2018 camera models",
    "authors": "Kitware Inc. and IARPA",
    "licence": "CC BY 4.0 (https://creativecommons.org/licenses/by/4.0/)",
    "source": "https://gitlab.kitware.com/meva/meva-data-repo (GitHub copy: "
    "KeivanShariatmadar/meva-data), metadata/camera-models/old/2018-03/",
    "landmarks": "the points Kitware's annotators clicked in the frames to calibrate the "
    "cameras (tracks.txt), lens corrected, kept where within 2 px (Sampson) of the calibration",
}
GOPRO_SOURCE = {
    "title": "EPFL multi-camera GoPro rig (four GoPro HERO6 across a hall)",
    "authors": "EPFL CVLab, as shipped by Leonardo Citraro in lcit/pypom",
    "licence": "GPL-3.0 (the lcit/pypom repository)",
    "source": "https://github.com/lcit/pypom, examples/full_example/",
    "landmarks": "tape crossings on the floor (measured on top views of the floor rendered "
    "from the frames), the hanging clock (triangulated from hand picks) and the cameras, "
    "projected with the calibration where visible (testbed/real_cameras_gopro.py): exact for "
    "the calibration, which itself is good to a few px",
}


# --- writing -------------------------------------------------------------------------------


def write(
    path: Path,
    source: dict[str, str],
    cameras: dict[str, SourceCamera],
    landmarks: Iterable[Landmark],
    max_sampson: float,
) -> None:
    """Every pair of cameras that shares enough landmarks which agree with the calibration."""
    landmarks = list(landmarks)
    pairs = []
    for first, second in itertools.combinations(sorted(cameras), 2):
        stored = _pair(first, second, cameras, landmarks, max_sampson)
        if stored is not None:
            pairs.append(stored)
    document: dict[str, Any] = {
        **source,
        "pixels": "undistorted: cv2.undistortPoints(raw, K, distortion, P=K); x right, y down",
        "cameras": {
            name: {
                "image_size": list(camera.image_size),
                "intrinsics": camera.camera.intrinsics.tolist(),
                "rotation": camera.camera.rotation.tolist(),
                "translation": camera.camera.translation.tolist(),
                "distortion": camera.distortion.tolist(),
                "focal_35mm": round(camera_focal_35mm(camera.camera, camera.image_size), 1),
            }
            for name, camera in sorted(cameras.items())
        },
        "pairs": pairs,
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(_compact(json.dumps(document, indent=1)) + "\n")
    print(f"{path}: {len(pairs)} pairs, {sum(len(p['landmarks1']) for p in pairs)} landmarks")


def _pair(
    first: str,
    second: str,
    cameras: dict[str, SourceCamera],
    landmarks: list[Landmark],
    max_sampson: float,
) -> dict[str, Any] | None:
    shared = [m for m in landmarks if first in m.pixels and second in m.pixels]
    if len(shared) < MIN_LANDMARKS:
        return None
    one, two = cameras[first], cameras[second]
    # Rounded as written, so that the stored distances are those of the stored pixels.
    points1 = np.round(np.array([m.pixels[first] for m in shared]), 2)
    points2 = np.round(np.array([m.pixels[second] for m in shared]), 2)
    probe = RealPair(
        "probe", (first, second), one.camera, two.camera, one.image_size, two.image_size,
        points1, points2, accuracy=math.inf,
    )  # fmt: skip
    sampson = probe.sampson()
    kept = (sampson <= max_sampson) & probe.in_front()
    kept &= inside(points1, one.image_size) & inside(points2, two.image_size)
    friend_visible = probe.friend_visible or reversed_pair(probe).friend_visible
    if kept.sum() < MIN_LANDMARKS or not friend_visible:
        return None
    return {
        "cameras": [first, second],
        "truth": _truth(probe),
        "landmarks": [m.name for m, k in zip(shared, kept, strict=True) if k],
        "landmarks1": points1[kept].tolist(),
        "landmarks2": points2[kept].tolist(),
        "sampson_px": np.round(sampson[kept], 3).tolist(),
        "accuracy_px": math.ceil(100 * float(sampson[kept].max())) / 100,
    }


def _truth(pair: RealPair) -> dict[str, Any]:
    """What the calibration says of the pair, for a reader (the loader recomputes it)."""
    return {
        "epipole1": np.round(pair.epipole1, 1).tolist(),
        "epipole2": np.round(pair.epipole2, 1).tolist(),
        "camera2_in_front_of_camera1": bool(pair.epipole1_h[2] > 0),
        "camera1_in_front_of_camera2": bool(pair.epipole2_h[2] > 0),
        "axes_angle_deg": round(pair.axes_angle_deg, 1),
    }


def _compact(text: str) -> str:
    """JSON with every innermost list of numbers on one line."""
    return re.sub(r"\[[^\[\]{}\"]*\]", lambda m: re.sub(r"\s+", " ", m.group(0)), text)


if __name__ == "__main__":
    main()
