"""Real calibrated photographs for the solver: pairs of real cameras, their true geometry and
the landmarks both photos show (``tests/data/real_cameras/``, sources and licences in its
README; ``testbed/real_cameras_build.py`` derives them from the source data).

Every pixel here is in the *undistorted* frame of its photo: the lens already corrected with
the camera's own calibration (``cv2.undistortPoints(..., P=K)``), as a phone's camera app
does, so each camera is a pinhole ``x = K [R | t] X`` (:class:`testbed.scenes.Camera`).

A :class:`RealPair` is oriented like ``solve``'s input: the friend marked in photo 1 is
camera 2 (``epipole1``, inside photo 1, so a person can tap them), the answer is camera 1 in
photo 2 (``epipole2``), inside photo 2 ("facing": each camera in the other's photo), in front
of camera 2 but outside its photo ("arrow": the app draws an arrow at the border), or behind
camera 2 ("behind": the app says turn around). Facing pairs appear in both orientations.

:func:`zoomed` makes the photo a phone zoomed 2x, 3x or 5x would have taken from the same
place (a centred crop scaled back to the same pixel size), :func:`tap` what a person taps:
every landmark in a random order (draw ``k`` of them with ``Taps.first(k)``: nested, so ``k``
and ``k + 1`` landmarks share their first ``k``) and the friend, each with tap noise.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cache
from pathlib import Path
from typing import Any, Literal

import cv2
import numpy as np

from shared_solver.estimation.camera import focal_35mm
from shared_solver.estimation.epipolar_fit import sampson_distances
from shared_solver.projective import Array, Indices, Mask, unit
from testbed.scenes import Camera, Scene, inside

DATA = Path(__file__).resolve().parent.parent / "tests" / "data" / "real_cameras"
# The sets, one JSON file each in DATA (its README says where each comes from).
SETS = ("epfl_gopro_rig", "meva_2018_03")

PairKind = Literal["facing", "arrow", "behind"]


@dataclass(frozen=True)
class RealPair:
    """Two real photos, their calibrated cameras and the landmarks both show.

    Attributes:
        set_name: the set it comes from (a file in ``DATA``).
        camera_ids: the two cameras' names in the set, photo 1's first.
        camera1, camera2: the true cameras, in the undistorted pixel frame.
        image_size1, image_size2: (width, height) of the photos, px.
        landmarks1, landmarks2: (N, 2) the same N landmarks in photo 1 and photo 2, px.
        accuracy: px, what the landmarks are stated to be good to: the largest Sampson
            distance of any landmark of the pair to the true geometry.
        zoom2: the zoom of photo 2 over the camera that took it (1 for the real photo).
    """

    set_name: str
    camera_ids: tuple[str, str]
    camera1: Camera
    camera2: Camera
    image_size1: tuple[int, int]
    image_size2: tuple[int, int]
    landmarks1: Array
    landmarks2: Array
    accuracy: float
    zoom2: float = 1.0

    @property
    def name(self) -> str:
        """ "<set> <camera 1>-<camera 2>", and the zoom of photo 2 when it is zoomed."""
        zoom = "" if self.zoom2 == 1.0 else f" zoom {self.zoom2:g}x"
        return f"{self.set_name} {self.camera_ids[0]}-{self.camera_ids[1]}{zoom}"

    @property
    def fundamental(self) -> Array:
        """(3, 3) the true F, unit norm: ``x2^T F x1 = 0``."""
        no_points = np.zeros((0, 3))
        return Scene(
            self.camera1, self.camera2, no_points, self.image_size1, self.image_size2
        ).fundamental

    @property
    def epipole1_h(self) -> Array:
        """(3,) camera 2 seen by camera 1, unit norm, oriented: ``w > 0`` in front of camera 1."""
        return _seen(self.camera1, self.camera2.centre)

    @property
    def epipole2_h(self) -> Array:
        """(3,) camera 1 seen by camera 2 (the answer), oriented as ``epipole1_h``."""
        return _seen(self.camera2, self.camera1.centre)

    @property
    def epipole1(self) -> Array:
        """(2,) where friend 2 is in photo 1, px."""
        return self.epipole1_h[:2] / self.epipole1_h[2]

    @property
    def epipole2(self) -> Array:
        """(2,) where friend 1 is in photo 2, px (behind camera 2 when ``kind == "behind"``)."""
        return self.epipole2_h[:2] / self.epipole2_h[2]

    @property
    def diagonal2(self) -> float:
        """Photo 2's diagonal, px: what errors are measured against."""
        return math.hypot(*self.image_size2)

    @property
    def kind(self) -> PairKind:
        """Where the answer is: in photo 2, in front of camera 2 but outside, or behind."""
        if self.epipole2_h[2] <= 0.0:
            return "behind"
        return "facing" if _inside(self.epipole2, self.image_size2) else "arrow"

    @property
    def friend_visible(self) -> bool:
        """Whether friend 2 is in front of camera 1 and inside photo 1 (a person can tap them)."""
        return bool(self.epipole1_h[2] > 0.0) and _inside(self.epipole1, self.image_size1)

    @property
    def axes_angle_deg(self) -> float:
        """The angle between the cameras' optical axes, degrees (180: aimed at each other)."""
        cosine = float(self.camera1.rotation[2] @ self.camera2.rotation[2])
        return math.degrees(math.acos(max(-1.0, min(1.0, cosine))))

    @property
    def off_axis2_deg(self) -> float:
        """How far friend 1 is from camera 2's optical axis, degrees."""
        ray = self.camera2.rotation @ (self.camera1.centre - self.camera2.centre)
        return math.degrees(math.acos(max(-1.0, min(1.0, ray[2] / float(np.linalg.norm(ray))))))

    @property
    def focal_35mm1(self) -> float:
        """Photo 1's 35 mm-equivalent focal length, mm (what EXIF would say)."""
        return camera_focal_35mm(self.camera1, self.image_size1)

    @property
    def focal_35mm2(self) -> float:
        """Photo 2's 35 mm-equivalent focal length, mm (zoom included)."""
        return camera_focal_35mm(self.camera2, self.image_size2)

    def sampson(self) -> Array:
        """(N,) each landmark's Sampson distance to the true geometry, px."""
        return np.abs(sampson_distances(self.fundamental, self.landmarks1, self.landmarks2))

    def in_front(self) -> Mask:
        """(N,) whether each landmark, triangulated with the true cameras, is in front of both."""
        points = triangulate(self.camera1, self.camera2, self.landmarks1, self.landmarks2)
        return (self.camera1.depth(points) > 0) & (self.camera2.depth(points) > 0)


@dataclass(frozen=True)
class Taps:
    """What one person taps on a pair: every landmark in a random order, and the friend.

    Attributes:
        points1, points2: (N, 2) the landmarks in the drawn order, each tap with its noise.
        epipole1: (2,) friend 2 marked in photo 1: the true position plus tap noise.
        order: (N,) the landmarks' indices in the pair, in the drawn order.
    """

    points1: Array
    points2: Array
    epipole1: Array
    order: Indices

    def first(self, count: int) -> tuple[Array, Array]:
        """The first ``count`` landmarks in both photos: a subset of the first ``count + 1``."""
        if not 0 < count <= len(self.order):
            raise ValueError(f"{count} landmarks asked, {len(self.order)} drawn")
        return self.points1[:count], self.points2[:count]


def tap(pair: RealPair, rng: np.random.Generator, sigma: float) -> Taps:
    """A person's taps on ``pair``: the landmarks shuffled, every tap off by N(0, sigma^2) px
    in x and y (the friend's mark included)."""
    count = len(pair.landmarks1)
    order = rng.permutation(count)
    noise = rng.normal(0.0, sigma, (2 * count + 1, 2))
    return Taps(
        points1=pair.landmarks1[order] + noise[:count],
        points2=pair.landmarks2[order] + noise[count : 2 * count],
        epipole1=pair.epipole1 + noise[-1],
        order=order,
    )


def zoomed(pair: RealPair, zoom: float) -> RealPair:
    """The pair with photo 2 taken zoomed in ``zoom`` times from the same place.

    A phone's zoom (digital, or a longer lens on the same axis) is a crop about the photo's
    centre ``c`` scaled back to the same pixel size: ``x' = zoom (x - c) + c``, so
    ``K' = Z K`` with ``Z = [[zoom, 0, (1 - zoom) cx], [0, zoom, (1 - zoom) cy], [0, 0, 1]]``.
    The landmarks that leave the crop are dropped; the truth (F, the epipoles) follows from
    the new camera.
    """
    if zoom < 1.0:
        raise ValueError("a zoom is at least 1")
    width, height = pair.image_size2
    centre = np.array([width / 2.0, height / 2.0])
    crop = np.array(
        [[zoom, 0.0, (1.0 - zoom) * centre[0]], [0.0, zoom, (1.0 - zoom) * centre[1]], [0, 0, 1]]
    )
    landmarks2 = zoom * (pair.landmarks2 - centre) + centre
    kept = inside(landmarks2, pair.image_size2)
    camera2 = replace(pair.camera2, intrinsics=crop @ pair.camera2.intrinsics)
    return replace(
        pair,
        camera2=camera2,
        landmarks1=pair.landmarks1[kept],
        landmarks2=landmarks2[kept],
        accuracy=pair.accuracy * zoom,
        zoom2=pair.zoom2 * zoom,
    )


def reversed_pair(pair: RealPair) -> RealPair:
    """The same two photos with their roles swapped (photo 2 becomes photo 1)."""
    if pair.zoom2 != 1.0:
        raise ValueError("reverse the real pair, then zoom")
    return replace(
        pair,
        camera_ids=(pair.camera_ids[1], pair.camera_ids[0]),
        camera1=pair.camera2,
        camera2=pair.camera1,
        image_size1=pair.image_size2,
        image_size2=pair.image_size1,
        landmarks1=pair.landmarks2,
        landmarks2=pair.landmarks1,
    )


def load_pairs(sets: Sequence[str] = SETS, directory: Path = DATA) -> list[RealPair]:
    """Every pair of every set, oriented so that friend 2 is inside photo 1 (facing pairs in
    both orientations, the others in the one where the friend can be tapped)."""
    pairs: list[RealPair] = []
    for name in sets:
        for pair in stored_pairs(name, directory):
            pairs += [
                oriented for oriented in (pair, reversed_pair(pair)) if oriented.friend_visible
            ]
    return pairs


@cache
def stored_pairs(name: str, directory: Path = DATA) -> tuple[RealPair, ...]:
    """The pairs of one set as stored (``<directory>/<name>.json``), in the stored order."""
    document = read_set(name, directory)
    cameras = {key: _camera(value) for key, value in document["cameras"].items()}
    pairs = []
    for stored in document["pairs"]:
        first, second = stored["cameras"]
        pairs.append(
            RealPair(
                set_name=name,
                camera_ids=(first, second),
                camera1=cameras[first][0],
                camera2=cameras[second][0],
                image_size1=cameras[first][1],
                image_size2=cameras[second][1],
                landmarks1=np.array(stored["landmarks1"], dtype=np.float64),
                landmarks2=np.array(stored["landmarks2"], dtype=np.float64),
                accuracy=float(stored["accuracy_px"]),
            )
        )
    return tuple(pairs)


def read_set(name: str, directory: Path = DATA) -> dict[str, Any]:
    """The JSON document of one set, as stored."""
    document: dict[str, Any] = json.loads((directory / f"{name}.json").read_text())
    return document


def triangulate(camera1: Camera, camera2: Camera, points1: Array, points2: Array) -> Array:
    """(N, 3) world points of (N, 2) matching pixels (OpenCV's linear triangulation)."""
    p1 = camera1.intrinsics @ np.column_stack([camera1.rotation, camera1.translation])
    p2 = camera2.intrinsics @ np.column_stack([camera2.rotation, camera2.translation])
    points = cv2.triangulatePoints(
        p1, p2, points1.T.astype(np.float64), points2.T.astype(np.float64)
    )
    return (points[:3] / points[3]).T


def _camera(stored: dict[str, Any]) -> tuple[Camera, tuple[int, int]]:
    width, height = stored["image_size"]
    camera = Camera(
        intrinsics=np.array(stored["intrinsics"], dtype=np.float64),
        rotation=np.array(stored["rotation"], dtype=np.float64),
        translation=np.array(stored["translation"], dtype=np.float64),
    )
    return camera, (int(width), int(height))


def _seen(camera: Camera, point: Array) -> Array:
    """(3,) the oriented image of a world point: unit norm, ``w`` its depth's sign."""
    return unit(camera.intrinsics @ (camera.rotation @ point + camera.translation))


def camera_focal_35mm(camera: Camera, size: tuple[int, int]) -> float:
    """The 35 mm-equivalent focal length (mm) of ``camera`` on a photo of ``size``."""
    intrinsics = camera.intrinsics
    return focal_35mm(math.sqrt(intrinsics[0, 0] * intrinsics[1, 1]), size)


def _inside(pixel: Array, size: tuple[int, int]) -> bool:
    return bool(inside(pixel[None], size)[0])


# --- how far an answer is from the truth -----------------------------------------------

# Friend 1 this far outside photo 2 (fraction of the diagonal) is still "near": the app
# draws the answer's distance, and a position error (% of the diagonal) still means
# something; further out it draws an arrow (an error in degrees).
NEAR = 0.10


def group(pair: RealPair) -> Literal["near", "arrow", "behind"]:
    """Where the answer is: in or near photo 2, outside it (an arrow), behind camera 2."""
    if pair.kind == "behind":
        return "behind"
    if _outside_by(pair.epipole2, pair.image_size2) <= NEAR * pair.diagonal2:
        return "near"
    return "arrow"


def _outside_by(pixel: Array, size: tuple[int, int]) -> float:
    """How far a pixel is beyond the photo's border, px (0 inside)."""
    x, y = pixel
    return max(0.0, -x, x - size[0], -y, y - size[1])


def error(
    pair: RealPair,
    pixel: Sequence[float] | None,
    homogeneous: Sequence[float] | None,
) -> float:
    """How far an answer (friend 1 in photo 2: its pixel, None at infinity or behind, and
    its oriented homogeneous point) is from the truth: % of photo 2's diagonal when friend 1
    is in or near photo 2; otherwise degrees between the arrow the answer draws (from photo
    2's centre) and the true direction, 180 for an answer behind camera 2 (the app says turn
    around); inf for no answer; nan when the truth is behind camera 2."""
    kind = group(pair)
    if kind == "behind":
        return math.nan
    if kind == "near":
        if pixel is None:
            return math.inf
        offset = float(np.linalg.norm(np.array(pixel) - pair.epipole2))
        return 100.0 * offset / pair.diagonal2
    centre = np.array(pair.image_size2) / 2.0
    if pixel is not None:
        direction = np.array(pixel) - centre
    elif homogeneous is not None and homogeneous[2] == 0.0:
        direction = np.array(homogeneous[:2])
    elif homogeneous is not None:
        return 180.0
    else:
        return math.inf
    return _angle(direction, pair.epipole2 - centre)


def _angle(a: Array, b: Array) -> float:
    cosine = float(a @ b) / (float(np.linalg.norm(a)) * float(np.linalg.norm(b)))
    return math.degrees(math.acos(max(-1.0, min(1.0, cosine))))


# --- what the sets are made of before they are written (real_cameras_build) ---------------


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
