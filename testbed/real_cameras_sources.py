"""What the real-camera sets are made of before they are written (``real_cameras_build``):
a source's calibrated cameras with their lens model, and its landmarks."""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from shared_solver.projective import Array
from testbed.scenes import Camera


@dataclass(frozen=True)
class SourceCamera:
    """A calibrated camera as its source gives it: the lens model and the photo's size."""

    camera: Camera  # K, R, t; K is also the undistorted frame's K
    distortion: Array  # OpenCV's (k1, k2, p1, p2[, k3])
    image_size: tuple[int, int]

    def undistort(self, pixels: Array) -> Array:
        """(N, 2) raw pixels -> (N, 2) pixels of the lens-corrected photo (same K)."""
        k = self.camera.intrinsics
        points = pixels.reshape(-1, 1, 2).astype(np.float64)
        corrected = cv2.undistortPoints(points, k, self.distortion, P=k)
        return np.asarray(corrected, dtype=np.float64).reshape(-1, 2)


@dataclass(frozen=True)
class Landmark:
    """One landmark seen by several cameras: its pixel in each (undistorted frame), and a
    name that says where it comes from."""

    name: str
    pixels: dict[str, Array]  # camera -> (2,) pixel in the undistorted frame
