"""The EPFL GoPro rig's landmarks, measured in its four frames (``real_cameras_build``).

Four GoPro HERO6 on tripods at the corners of a hall, facing inwards: their wide, strongly
distorted lenses see each other across the hall, but from opposite sides the hall looks so
different that no feature matcher pairs its points (SIFT with the ratio test: 0 to 2 matches
per pair agree with the calibration). The landmarks are therefore 3-D points of the hall,
measured in the photos and seen through the calibration, as a person would tap them:

* the crossings of the tape on the floor (two tape ladders and T marks): each crossing's
  centre is measured on a top view of the floor rendered from the frame that sees it best
  (the calibration maps the floor plane, z = 0, into each photo), as the intersection of the
  two tapes' centre lines (``epfl_gopro_rig_landmarks.json`` gives where to look);
* the double-sided clock hanging in the middle of the hall, triangulated from its centre
  picked by hand in the three frames that show it;
* each camera on its tripod, where another camera sees it (its centre is the calibration's).

Each landmark is then projected into every photo where it is in front of the camera, inside
the frame and not hidden (``hidden_in``: behind a wall, a pillar or the printer, judged by eye
on the frames): consistent with the calibration by construction. The calibration itself
is good to a few pixels (it puts its own floor points 0.7-6.3 px from where pypom's example
clicked them in camera 0), which sets how well the truth is known on this rig.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from shared_solver.projective import Array
from testbed.real_cameras import Landmark, SourceCamera
from testbed.scenes import Camera, inside

CAMERAS = ("0", "1", "2", "3")
# Metres per calibration unit: the rig's translations are in cm.
CM = 0.01
# Top views of the floor: 2 mm per pixel, a window of 40 cm either side of the crossing.
TOP_VIEW_PX_M = 0.002
TOP_VIEW_HALF_M = 0.40
# How far along each tape its centre line is sampled, m (clear of the crossing itself).
TAPE_NEAR_M, TAPE_FAR_M = 0.06, 0.30
# A landmark this close to a photo's border is not kept: nobody taps the very edge.
EDGE_MARGIN = 0.02


def gopro(directory: Path, landmarks_file: Path) -> tuple[dict[str, SourceCamera], list[Landmark]]:
    """The rig's cameras (metres) and its landmarks in the undistorted frames."""
    cameras = {name: _camera(directory, name) for name in CAMERAS}
    frames = {name: _frame(directory / f"frame_gopro6.{name}.jpg") for name in CAMERAS}
    spec = json.loads(landmarks_file.read_text())
    points: dict[str, tuple[Array, set[str]]] = {}
    for name, crossing in spec["floor_crossings"].items():
        points[name] = _crossing(cameras, frames, crossing), set(crossing["hidden_in"])
    for name, picked in spec["picked"].items():
        points[name] = _triangulated(cameras, picked["pixels"]), set(picked["hidden_in"])
    for name, camera in cameras.items():
        # A camera on its tripod, for the others; not for itself.
        points[f"camera {name}"] = camera.camera.centre, {name}
    landmarks = []
    for name, (point, hidden) in points.items():
        pixels = {}
        for camera_name, camera in cameras.items():
            seen = _seen(camera, point)
            if seen is not None and camera_name not in hidden:
                pixels[camera_name] = seen
        landmarks.append(Landmark(name, pixels))
    return cameras, landmarks


def _frame(path: Path) -> Array:
    image = cv2.imread(str(path))
    if image is None:
        raise FileNotFoundError(path)
    return np.asarray(image)


def _camera(directory: Path, name: str) -> SourceCamera:
    intrinsics = json.loads(
        (directory / "calibration" / f"intrinsics_gopro6.{name}.json").read_text()
    )
    extrinsics = json.loads(
        (directory / "calibration" / f"extrinsics_gopro6.{name}.json").read_text()
    )
    k = np.array(intrinsics["K"], dtype=np.float64)
    height, width = intrinsics["image_shape"]
    camera = Camera(
        k,
        np.array(extrinsics["R"], dtype=np.float64),
        CM * np.array(extrinsics["t"], dtype=np.float64).ravel(),
    )
    distortion = np.array(intrinsics["distCoeffs"], dtype=np.float64).ravel()
    return SourceCamera(camera, distortion, (int(width), int(height)))


def _seen(camera: SourceCamera, point: Array) -> Array | None:
    """Where a world point is in the undistorted photo, if in front and inside the frame."""
    if camera.camera.depth(point[None])[0] <= 0.0:
        return None
    pixel = camera.camera.project(point[None])
    width, height = camera.image_size
    margin = EDGE_MARGIN * np.array([width, height])
    if not inside(pixel - margin, (int(width - 2 * margin[0]), int(height - 2 * margin[1])))[0]:
        return None
    return pixel[0]


def _crossing(
    cameras: dict[str, SourceCamera], frames: dict[str, Array], crossing: dict[str, Any]
) -> Array:
    """(3,) the centre of a tape crossing on the floor, m, measured on a top view.

    ``crossing``: ``near`` (x, y) in cm, where to look; ``along_x`` and ``along_y``: on
    which sides of the crossing each tape runs ("both", or -1 / +1 for one side).
    """
    near = CM * np.array(crossing["near"], dtype=np.float64)
    name = max(cameras, key=lambda n: _resolution(cameras[n], near))
    view, origin = _top_view(cameras[name], frames[name], near)
    # The tape running along y fixes x, and the one along x fixes y.
    x = _tape_centre(view, origin, near, axis=0, sides=crossing["along_y"])
    y = _tape_centre(view, origin, near, axis=1, sides=crossing["along_x"])
    return np.array([x, y, 0.0])


def _resolution(camera: SourceCamera, floor_point: Array) -> float:
    """Pixels per metre of floor at ``floor_point`` in this photo (0 when not seen)."""
    base = np.array([floor_point[0], floor_point[1], 0.0])
    if _seen(camera, base) is None:
        return 0.0
    steps = base + np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.0, 0.01, 0.0]])
    pixels = camera.camera.project(steps)
    return float(min(np.linalg.norm(pixels[1:] - pixels[0], axis=1)) / 0.01)


def _top_view(camera: SourceCamera, frame: Array, near: Array) -> tuple[Array, Array]:
    """A grey top view of the floor around ``near`` rendered from the raw frame (lens model
    applied), and the world (x, y) of its pixel (0, 0); x to the right, y down."""
    steps = np.arange(-TOP_VIEW_HALF_M, TOP_VIEW_HALF_M + 1e-9, TOP_VIEW_PX_M)
    grid_x, grid_y = np.meshgrid(near[0] + steps, near[1] + steps)
    world = np.column_stack([grid_x.ravel(), grid_y.ravel(), np.zeros(grid_x.size)])
    rotation = cv2.Rodrigues(camera.camera.rotation)[0]
    raw, _ = cv2.projectPoints(
        world, rotation, camera.camera.translation, camera.camera.intrinsics, camera.distortion
    )
    maps = raw.reshape(*grid_x.shape, 2).astype(np.float32)
    grey = cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY)
    view = cv2.remap(grey, maps[..., 0], maps[..., 1], cv2.INTER_LINEAR).astype(np.float64)
    return view, near[:2] - TOP_VIEW_HALF_M


def _tape_centre(view: Array, origin: Array, near: Array, *, axis: int, sides: Any) -> float:
    """The world coordinate (m) of a tape's centre line along ``axis`` (0: x, 1: y), from
    profiles across it averaged over the stretches where it runs (clear of the crossing)."""
    centre = (near[:2] - origin) / TOP_VIEW_PX_M
    near_px, far_px = TAPE_NEAR_M / TOP_VIEW_PX_M, TAPE_FAR_M / TOP_VIEW_PX_M
    stretches = [-1, 1] if sides == "both" else [int(sides)]
    half_width = 0.05 / TOP_VIEW_PX_M  # search 5 cm either side of where it should be
    across = np.arange(round(centre[axis] - half_width), round(centre[axis] + half_width))
    profiles = []
    for side in stretches:
        start, stop = sorted((centre[1 - axis] + side * near_px, centre[1 - axis] + side * far_px))
        rows = np.arange(round(start), round(stop))
        block = view[rows][:, across] if axis == 0 else view[across][:, rows].T
        profiles.append(block.mean(axis=0))
    profile = np.mean(profiles, axis=0)
    return float(origin[axis] + TOP_VIEW_PX_M * _ridge(profile, across.astype(np.float64)))


def _ridge(profile: Array, positions: Array) -> float:
    """The centre of the bright band in ``profile``: the centroid of its upper half."""
    smooth = np.convolve(profile, np.ones(5) / 5, mode="same")
    peak = int(np.argmax(smooth[2:-2])) + 2
    base = float(np.median(smooth))
    half = base + (smooth[peak] - base) / 2
    low, high = peak, peak
    while low > 0 and smooth[low - 1] > half:
        low -= 1
    while high < len(smooth) - 1 and smooth[high + 1] > half:
        high += 1
    weights = smooth[low : high + 1] - half
    return float(np.sum(positions[low : high + 1] * weights) / np.sum(weights))


def _triangulated(cameras: dict[str, SourceCamera], picks: dict[str, Any]) -> Array:
    """(3,) the least-squares (DLT) point of a feature picked by hand in several frames
    (``picks``: camera -> (x, y) in the undistorted frame)."""
    rows = []
    for name, (x, y) in picks.items():
        camera = cameras[name].camera
        projection = camera.intrinsics @ np.column_stack([camera.rotation, camera.translation])
        rows += [x * projection[2] - projection[0], y * projection[2] - projection[1]]
    solution = np.linalg.svd(np.array(rows))[2][-1]
    return solution[:3] / solution[3]
