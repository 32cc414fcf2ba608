"""The MEVA March 2018 camera models and the landmarks Kitware's annotators clicked to
calibrate them (``real_cameras_build --meva``).

The outdoor surveillance cameras of the MEVA collection (a school, a bus station, a
hospital's grounds), calibrated into one east-north-up frame in metres: ``cameras/*.krtd``
(K, R, t, OpenCV distortion), ``landmarks.ply`` (3-D points) and ``tracks.txt`` (where each
was clicked in each camera's frame, ``frames.txt`` numbering the cameras). The clicks are
kept, lens corrected.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from shared_solver.projective import Array
from testbed.real_cameras import Landmark, SourceCamera
from testbed.scenes import Camera


def meva(directory: Path) -> tuple[dict[str, SourceCamera], list[Landmark]]:
    """MEVA's calibrated cameras and the annotated landmarks (tracks.txt) they share."""
    names = [line.strip() for line in (directory / "frames.txt").read_text().splitlines()]
    names = [Path(line).stem for line in names if line]
    cameras = {
        path.stem: _krtd(path, directory / "frames" / f"{path.stem}.png")
        for path in sorted((directory / "cameras").glob("*.krtd"))
    }
    seen: dict[int, dict[str, Array]] = {}
    for line in (directory / "tracks.txt").read_text().splitlines():
        fields = line.split()
        if len(fields) < 4:
            continue
        track, frame = int(fields[0]), names[int(fields[1]) - 1]
        if frame in cameras:
            raw = np.array([[float(fields[2]), float(fields[3])]])
            seen.setdefault(track, {})[frame] = cameras[frame].undistort(raw)[0]
    landmarks = [Landmark(f"track {track}", pixels) for track, pixels in sorted(seen.items())]
    return cameras, landmarks


def _krtd(path: Path, frame: Path) -> SourceCamera:
    """A KRTD file: K (3x3), R (3x3), t (3), then OpenCV distortion coefficients."""
    values = [float(v) for v in path.read_text().split()]
    intrinsics = np.array(values[:9]).reshape(3, 3)
    camera = Camera(intrinsics, np.array(values[9:18]).reshape(3, 3), np.array(values[18:21]))
    distortion = np.zeros(4)
    distortion[: len(values) - 21] = values[21:25]
    image = cv2.imread(str(frame)) if frame.exists() and frame.stat().st_size else None
    if image is not None:
        size = (int(image.shape[1]), int(image.shape[0]))
    else:  # the frame is not in the repository: its principal point is the pixel centre
        size = (round(2 * intrinsics[0, 2] + 1), round(2 * intrinsics[1, 2] + 1))
    return SourceCamera(camera, distortion, size)
