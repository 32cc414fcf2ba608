"""Synthetic and calibrated two-camera scenes, for tests, benchmarks and the demo.

A *facing scene* is the search for a friend: two phones across a venue, each aimed at the other
(so each sees the other: both epipoles are inside the photos), landmarks between them. The
*temple* scenes use the real calibration of the Middlebury templeSparseRing set.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from shared_solver import solve
from shared_solver.projective import Array, Mask, skew
from shared_solver.result import SolveResult

# Tight bounding box of the templeSparseRing model (metres), from the dataset's README.
TEMPLE_BOX = (np.array([-0.073568, 0.021728, -0.012445]), np.array([0.028855, 0.181892, 0.062736]))
TEMPLE_IMAGE_SIZE = (640, 480)
_MAX_DRAWS = 200
# Taps on two 640x480 photos that no two phone cameras explain (found by a search with
# ``solve``'s own camera model and its wider search): no pose for the first three
# landmarks, only the curve from four (the fit fails its test), the projective answer from
# five. What a cropped or edited photo, or mixed-up landmarks, can give.
NO_PHONES_LANDMARKS1 = np.array([[444, 193], [451, 121], [237, 360], [280, 244], [275, 61]], float)
NO_PHONES_LANDMARKS2 = np.array([[325, 40], [115, 343], [466, 447], [470, 195], [143, 112]], float)
NO_PHONES_FRIEND = (173.0, 422.0)


@dataclass(frozen=True)
class Camera:
    """A pinhole camera ``x = K [R | t] X`` with pixel coordinates x right, y down."""

    intrinsics: Array
    rotation: Array
    translation: Array

    @property
    def centre(self) -> Array:
        """(3,) camera centre in world coordinates."""
        return -self.rotation.T @ self.translation

    @property
    def down(self) -> Array:
        """(3,) unit vector of down (the world's y) in the camera's frame (x right, y down,
        z into the scene): what its phone's gravity reads, held still."""
        down: Array = self.rotation[:, 1].copy()
        return down

    @property
    def heading(self) -> float:
        """Degrees clockwise from north (the world's z; east is its x) of the lens axis's
        horizontal direction: what its phone's compass reads, undisturbed."""
        axis = self.rotation[2]  # the lens axis in world coordinates
        return math.degrees(math.atan2(axis[0], axis[2])) % 360.0

    def depth(self, points: Array) -> Array:
        """(N,) depth along the optical axis of (N, 3) world points (positive: in front)."""
        return points @ self.rotation[2] + self.translation[2]

    def project(self, points: Array) -> Array:
        """(N, 3) world points -> (N, 2) pixels."""
        image = (points @ self.rotation.T + self.translation) @ self.intrinsics.T
        return image[:, :2] / image[:, 2:]


@dataclass(frozen=True)
class Scene:
    """Two cameras and 3-D landmarks seen by both; ground truth for every solver."""

    camera1: Camera
    camera2: Camera
    points: Array
    image_size1: tuple[int, int]
    image_size2: tuple[int, int]

    @property
    def landmarks1(self) -> Array:
        return self.camera1.project(self.points)

    @property
    def landmarks2(self) -> Array:
        return self.camera2.project(self.points)

    @property
    def epipole1(self) -> Array:
        """(2,) where camera 2 (friend 2) appears in photo 1."""
        return self.camera1.project(self.camera2.centre[None])[0]

    @property
    def epipole2(self) -> Array:
        """(2,) where camera 1 (friend 1) appears in photo 2."""
        return self.camera2.project(self.camera1.centre[None])[0]

    @property
    def sizes(self) -> dict[str, Any]:
        """``solve``'s photo sizes: ``image_size1`` and ``image_size2``."""
        return {"image_size1": self.image_size1, "image_size2": self.image_size2}

    @property
    def fundamental(self) -> Array:
        """(3, 3) true F (unit norm) with ``x2^T F x1 = 0``."""
        c1, c2 = self.camera1, self.camera2
        rotation = c2.rotation @ c1.rotation.T
        translation = c2.translation - rotation @ c1.translation
        essential = skew(translation) @ rotation
        f = np.linalg.inv(c2.intrinsics).T @ essential @ np.linalg.inv(c1.intrinsics)
        return f / np.linalg.norm(f)


def look_at(centre: Array, target: Array, roll: float = 0.0) -> tuple[Array, Array]:
    """(R, t) of a camera at ``centre`` looking at ``target``, world y pointing down."""
    forward = (target - centre) / np.linalg.norm(target - centre)
    right = np.cross(forward, np.array([0.0, -1.0, 0.0]))
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    c, s = math.cos(roll), math.sin(roll)
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ np.stack(
        [right, down, forward]
    )
    return rotation, -rotation @ centre


def inside(pixels: Array, size: tuple[int, int]) -> Mask:
    """(N,) whether each of (N, 2) pixels is inside a photo of ``size`` (width, height)."""
    return (
        (pixels[:, 0] >= 0)
        & (pixels[:, 0] <= size[0])
        & (pixels[:, 1] >= 0)
        & (pixels[:, 1] <= size[1])
    )


def facing_scene(
    rng: np.random.Generator,
    landmarks: int,
    *,
    image_size: tuple[int, int] = (1600, 1200),
    focal: float = 1400.0,
    distance: float = 40.0,
    aim_jitter_deg: float = 6.0,
    planar: bool = False,
) -> Scene:
    """Two phones across a venue aimed at each other, landmarks between them.

    Args:
        rng: the random source (scenes are reproducible from its seed).
        landmarks: how many 3-D landmarks, each visible in both photos.
        image_size: (width, height) of both photos, px.
        focal: focal length of both cameras, px.
        distance: metres between the two phones.
        aim_jitter_deg: standard deviation of how far each phone points off the other.
        planar: put every landmark on the venue floor (a plane below both phones).
    """
    intrinsics = np.array(
        [[focal, 0.0, image_size[0] / 2], [0.0, focal, image_size[1] / 2], [0.0, 0.0, 1.0]]
    )
    jitter = distance * math.tan(math.radians(aim_jitter_deg))

    def draw(count: int) -> Array:
        depth = rng.uniform(0.2, 0.8, count) * distance
        # planar: the floor, 2.5 m below eye level (y is down)
        height = np.full(count, 2.5) if planar else rng.uniform(-6.0, 4.0, count)
        return np.column_stack([rng.uniform(-12.0, 12.0, count), height, depth])

    for _ in range(_MAX_DRAWS):
        centre1 = np.zeros(3)
        centre2 = np.array([rng.normal(0, 2.0), rng.normal(0, 1.0), distance])
        camera1 = Camera(
            intrinsics, *look_at(centre1, centre2 + rng.normal(0, jitter, 3), rng.normal(0, 0.05))
        )
        camera2 = Camera(
            intrinsics, *look_at(centre2, centre1 + rng.normal(0, jitter, 3), rng.normal(0, 0.05))
        )
        scene = Scene(camera1, camera2, np.zeros((0, 3)), image_size, image_size)
        if not (
            inside(scene.epipole1[None], image_size)[0]
            and inside(scene.epipole2[None], image_size)[0]
        ):
            continue
        sizes = (image_size, image_size)
        found = seen_scene(lambda: draw(4 * landmarks), (camera1, camera2), sizes, landmarks)
        if found is not None:
            return found
    raise RuntimeError("could not aim the cameras at each other over the landmarks")


def in_photo(
    camera: Camera, points: Array, image_size: tuple[int, int], margin: float = 0.0
) -> Mask:
    """(N,) which of the (N, 3) world points the camera sees in its photo.

    Seen: in front of the camera and at least ``margin`` (fraction of each side) inside the
    borders of the ``image_size`` (width, height) px photo. A point behind the camera also
    projects somewhere, so the depth test matters.
    """
    front = camera.depth(points) > 0
    pixels = np.full((len(points), 2), np.nan)
    pixels[front] = camera.project(points[front])
    low = margin * np.asarray(image_size, dtype=float)
    high = (1.0 - margin) * np.asarray(image_size, dtype=float)
    return front & np.all((pixels >= low) & (pixels <= high), axis=1)


def seen_scene(
    draw: Callable[[], Array],
    cameras: tuple[Camera, Camera],
    sizes: tuple[tuple[int, int], tuple[int, int]],
    landmarks: int,
    margin: float = 0.0,
) -> Scene | None:
    """The scene of ``landmarks`` points from repeated ``draw()`` calls that both cameras
    see in their photos of ``sizes`` (width, height), ``margin`` inside the borders.

    ``draw`` returns (M, 3) candidate world points (m); the first ``landmarks`` that pass
    :func:`in_photo` for both cameras are kept, in draw order. None when a bounded number
    of draws does not find enough (the cameras share too little of the region ``draw``
    samples).
    """
    camera1, camera2 = cameras
    kept: list[Array] = []
    total = 0
    for _ in range(_MAX_DRAWS // 10):
        points = draw()
        ok = in_photo(camera1, points, sizes[0], margin) & in_photo(
            camera2, points, sizes[1], margin
        )
        kept.append(points[ok])
        total += int(ok.sum())
        if total >= landmarks:
            return Scene(camera1, camera2, np.vstack(kept)[:landmarks], *sizes)
    return None


def temple_cameras(parameters: Path) -> dict[str, Camera]:
    """Cameras of ``templeSR_par.txt`` by image name without extension (``templeSR0003``)."""
    cameras = {}
    lines = parameters.read_text().split("\n")
    for line in lines[1:]:
        fields = line.split()
        if len(fields) != 22:
            continue
        values = np.array([float(v) for v in fields[1:]])
        cameras[Path(fields[0]).stem] = Camera(
            values[0:9].reshape(3, 3), values[9:18].reshape(3, 3), values[18:21]
        )
    return cameras


def temple_scene(
    parameters: Path, name1: str, name2: str, landmarks: int, rng: np.random.Generator
) -> Scene:
    """Two real temple views and landmarks drawn in the model's bounding box."""
    cameras = temple_cameras(parameters)
    camera1, camera2 = cameras[name1], cameras[name2]
    low, high = TEMPLE_BOX
    sizes = (TEMPLE_IMAGE_SIZE, TEMPLE_IMAGE_SIZE)
    scene = seen_scene(
        lambda: rng.uniform(low, high, (4 * landmarks, 3)), (camera1, camera2), sizes, landmarks
    )
    if scene is None:
        raise ValueError(f"{name1} and {name2} see too little of the temple in common")
    return scene


@dataclass(frozen=True)
class Taps:
    """What two people's fingers report: every position with tap noise."""

    landmarks1: Array
    landmarks2: Array
    epipole1: Array
    epipole2: Array


def tap(scene: Scene, sigma: float, rng: np.random.Generator) -> Taps:
    """The scene's landmarks and both epipoles with Gaussian tap noise ``sigma`` px per axis."""
    n = len(scene.points)
    return Taps(
        scene.landmarks1 + rng.normal(0.0, sigma, (n, 2)),
        scene.landmarks2 + rng.normal(0.0, sigma, (n, 2)),
        scene.epipole1 + rng.normal(0.0, sigma, 2),
        scene.epipole2 + rng.normal(0.0, sigma, 2),
    )


def solved(scene: Scene, taps: Taps | None = None, **options: Any) -> SolveResult:
    """``shared_solver.solve`` on the scene: its exact landmarks and friend 1's mark (e1),
    or ``taps`` of them, with the photos' sizes; ``options`` as ``solve`` takes them."""
    seen: Scene | Taps = scene if taps is None else taps
    return solve(seen.landmarks1, seen.landmarks2, epipole1=seen.epipole1, **scene.sizes, **options)


def pixel(h: np.ndarray) -> np.ndarray:
    """The pixel (x, y) of a homogeneous point."""
    return h[:2] / h[2]


def line_through(point: np.ndarray, angle: float) -> np.ndarray:
    """(3,) line through a pixel point in the direction ``angle`` (radians)."""
    ahead = point + np.array([np.cos(angle), np.sin(angle)])
    return np.cross(np.append(point, 1.0), np.append(ahead, 1.0))


def marks(s: Scene, given: str, line_angle: float = 0.3) -> dict[str, Any]:
    """solve()'s marks of the friends: friend 2 tapped in photo 1 ("e1"), both friends, a
    line through friend 2 at ``line_angle`` (radians), or nothing."""
    return {
        "e1": {"epipole1": s.epipole1},
        "both": {"epipole1": s.epipole1, "epipole2": s.epipole2},
        "line": {"epipolar_line1": line_through(s.epipole1, line_angle)},
        "none": {},
    }[given]
