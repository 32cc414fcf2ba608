"""Realistic phone-photo scenes: the search for a friend as two real phones would shoot it.

``facing_scene`` in ``scenes.py`` keeps the geometry simple (one focal length, centred
principal points, one image size). Here each photo looks like what a current phone writes: a
12 MP frame in landscape or portrait, the main camera's ~26 mm (35 mm-equivalent) lens, an
optional zoom, a principal point a little off centre, and an EXIF focal length rounded to a
whole millimetre. The two phones stand 20-80 m apart across a theater, stadium or concert
hall, at heights a few metres apart (tiers, balconies), each aimed by hand at the other, and
the landmarks are the things of the venue both can see between them: seats, railings, signs,
pillars, stage corners.

World coordinates are metres with y pointing down (as ``look_at`` expects); pixels are x
right, y down.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from shared_solver.estimation.camera import PHONE_LOG_SIGMA
from shared_solver.projective import Array
from testbed.scenes import Camera, Scene, Taps, in_photo, look_at, seen_scene, tap

# The 35 mm equivalent focal length scales a lens to the 36 x 24 mm frame by the diagonal,
# whatever the photo's aspect ratio.
FRAME_DIAGONAL_MM = math.hypot(36.0, 24.0)
LANDSCAPE = (4032, 3024)
PORTRAIT = (3024, 4032)
MAIN_CAMERA_35MM = 26.0
# How far (fraction of each side) a landmark must stay from the photo's border: nobody taps
# the very edge of a photo, and a point on the border may be cut off by the preview.
EDGE_MARGIN = 0.02
_MAX_DRAWS = 200
_UP = np.array([0.0, -1.0, 0.0])


@dataclass(frozen=True)
class PhoneScene(Scene):
    """A :class:`Scene` shot with two phones, with what each phone knows of its own lens.

    ``focal_35mm1``/``2`` are the true 35 mm-equivalent focal lengths (mm, zoom included),
    ``exif_focal_35mm1``/``2`` what EXIF's FocalLengthIn35mmFilm says (the true value rounded
    to a whole mm), ``zoom1``/``2`` the zoom factors over the main camera.
    """

    focal_35mm1: float
    focal_35mm2: float
    exif_focal_35mm1: int
    exif_focal_35mm2: int
    zoom1: float
    zoom2: float

    @property
    def distance(self) -> float:
        """Metres between the two phones."""
        return float(np.linalg.norm(self.camera2.centre - self.camera1.centre))


def focal_pixels(focal_35mm: float, image_size: tuple[int, int]) -> float:
    """Focal length in px of a lens with this 35 mm-equivalent focal length (mm).

    ``image_size`` is (width, height) px; the equivalence is by the diagonal, so the answer is
    the same for a photo and its portrait turn.
    """
    return focal_35mm / FRAME_DIAGONAL_MM * math.hypot(*image_size)


def intrinsics(
    rng: np.random.Generator,
    focal_px: float,
    image_size: tuple[int, int],
    *,
    centre_sd: float = 0.003,
) -> Array:
    """(3, 3) K with square pixels, no skew, principal point near the photo's centre.

    The principal point is the centre of ``image_size`` (width, height) px plus a normal
    offset of ``centre_sd`` times the diagonal per axis: lenses are never mounted exactly
    over the sensor's middle.
    """
    offset = rng.normal(0.0, centre_sd * math.hypot(*image_size), 2)
    return np.array(
        [
            [focal_px, 0.0, image_size[0] / 2 + offset[0]],
            [0.0, focal_px, image_size[1] / 2 + offset[1]],
            [0.0, 0.0, 1.0],
        ]
    )


def aim(
    rng: np.random.Generator,
    centre: Array,
    target: Array,
    *,
    jitter_deg: float,
    roll_deg: float,
) -> tuple[Array, Array]:
    """(R, t) of a camera at ``centre`` (3,) m aimed by hand at ``target`` (3,) m.

    The optical axis misses the target by normal angles of sd ``jitter_deg`` sideways and
    up-down; the camera turns about its axis by a normal roll of sd ``roll_deg``.
    """
    offset = target - centre
    distance = float(np.linalg.norm(offset))
    forward = offset / distance
    side = np.cross(forward, _UP)
    side /= np.linalg.norm(side)
    up = np.cross(side, forward)
    yaw, pitch = np.tan(np.radians(rng.normal(0.0, jitter_deg, 2)))
    aimed = target + distance * (yaw * side + pitch * up)
    return look_at(centre, aimed, math.radians(rng.normal(0.0, roll_deg)))


def zoom_from_prior(rng: np.random.Generator) -> float:
    """A zoom factor over the main camera drawn from the solver's phone prior (log-normal,
    ``PHONE_LOG_SIGMA``): scenes on which that prior is exactly right, to check that the
    regions it gives hold the truth as often as they claim."""
    return float(math.exp(rng.normal(0.0, PHONE_LOG_SIGMA)))


def photo_size(rng: np.random.Generator) -> tuple[int, int]:
    """(width, height) px of a 12 MP phone photo, landscape or portrait at even odds."""
    return PORTRAIT if rng.random() < 0.5 else LANDSCAPE


def _half_field(camera: Camera, image_size: tuple[int, int]) -> float:
    """Tangent of the camera's half field of view across the photo's longer side."""
    return max(image_size) / 2 / float(camera.intrinsics[0, 0])


def phone_scene(
    rng: np.random.Generator,
    landmarks: int,
    *,
    zoom1: float = 1.0,
    zoom2: float = 1.0,
    distance: float | None = None,
    aim_jitter_deg: float = 3.0,
    roll_deg: float = 3.0,
    height_sd: float = 4.0,
    focal_sd: float = 0.05,
    centre_sd: float = 0.003,
) -> PhoneScene:
    """Two phones across a venue, each aimed at the other, landmarks of the venue between.

    Args:
        rng: the random source; the scene is reproducible from its seed.
        landmarks: how many 3-D landmarks, each in front of both phones and inside both
            photos with a margin of 2 % of the side.
        zoom1: zoom factor of photo 1 over the main camera (1: the ~26 mm lens).
        zoom2: the same for photo 2.
        distance: metres between the phones; uniform in 20-80 m when None.
        aim_jitter_deg: sd (degrees) of how far each phone points off the other, per axis.
        roll_deg: sd (degrees) of each phone's tilt about its optical axis.
        height_sd: sd (m) of the height of phone 2 over phone 1 (tiers, balconies).
        focal_sd: relative sd of the main camera's focal length around 26 mm.
        centre_sd: sd of each principal point's offset from the photo's centre, as a
            fraction of the diagonal (0: exactly centred, as exact-input tests need).

    Redraws phones until each sees the other (both epipoles inside both photos) and both
    share enough of the venue for ``landmarks`` points.
    """
    for _ in range(_MAX_DRAWS):
        span = rng.uniform(20.0, 80.0) if distance is None else distance
        # Phone 2's height over phone 1, at most half the distance (a steep tier, not a cliff).
        rise = float(np.clip(rng.normal(0.0, height_sd), -span / 2, span / 2))
        centre1 = np.zeros(3)
        centre2 = np.array([0.0, -rise, math.sqrt(span**2 - rise**2)])
        sizes = (photo_size(rng), photo_size(rng))
        focals = tuple(
            MAIN_CAMERA_35MM * (1.0 + rng.normal(0.0, focal_sd)) * zoom for zoom in (zoom1, zoom2)
        )
        camera1 = Camera(
            intrinsics(rng, focal_pixels(focals[0], sizes[0]), sizes[0], centre_sd=centre_sd),
            *aim(rng, centre1, centre2, jitter_deg=aim_jitter_deg, roll_deg=roll_deg),
        )
        camera2 = Camera(
            intrinsics(rng, focal_pixels(focals[1], sizes[1]), sizes[1], centre_sd=centre_sd),
            *aim(rng, centre2, centre1, jitter_deg=aim_jitter_deg, roll_deg=roll_deg),
        )
        # The search needs each phone in the other's photo.
        if not (
            in_photo(camera1, centre2[None], sizes[0])[0]
            and in_photo(camera2, centre1[None], sizes[1])[0]
        ):
            continue
        draw = _venue_points(
            rng,
            centre1,
            centre2,
            # Slack of ~6 degrees over the field of view: the phones point a little off.
            reach=(_half_field(camera1, sizes[0]) + 0.1, _half_field(camera2, sizes[1]) + 0.1),
            count=4 * landmarks,
        )
        seen = seen_scene(draw, (camera1, camera2), sizes, landmarks, EDGE_MARGIN)
        if seen is None:
            continue
        return PhoneScene(
            **vars(seen),
            focal_35mm1=focals[0],
            focal_35mm2=focals[1],
            exif_focal_35mm1=round(focals[0]),
            exif_focal_35mm2=round(focals[1]),
            zoom1=zoom1,
            zoom2=zoom2,
        )
    raise RuntimeError("could not aim the two phones at each other over the venue")


def gravity_reading(camera: Camera, sigma_deg: float, rng: np.random.Generator) -> Array:
    """(3,) unit: the camera's phone's gravity at the shutter, its true down (``camera.down``)
    turned by Gaussian noise of ``sigma_deg`` per axis (small angles)."""
    down = camera.down + rng.normal(0.0, math.radians(sigma_deg), 3)
    unit: Array = down / np.linalg.norm(down)
    return unit


def heading_reading(camera: Camera, sigma_deg: float, rng: np.random.Generator) -> float:
    """Degrees: the camera's phone's compass heading at the shutter (``camera.heading``)
    with Gaussian noise of ``sigma_deg``."""
    return camera.heading + float(rng.normal(0.0, sigma_deg))


def phone_taps(seed: int | Sequence[int], landmarks: int, sigma: float) -> tuple[PhoneScene, Taps]:
    """A phone scene of ``landmarks`` and its taps with ``sigma`` px of noise, both drawn from
    one generator seeded with ``seed``."""
    rng = np.random.default_rng(seed)
    scene = phone_scene(rng, landmarks)
    return scene, tap(scene, sigma, rng)


def _venue_points(
    rng: np.random.Generator,
    centre1: Array,
    centre2: Array,
    *,
    reach: tuple[float, float],
    count: int,
) -> Callable[[], Array]:
    """A draw of ``count`` (count, 3) candidate landmarks between the phones.

    Points lie 15-85 % of the way from phone 1 to phone 2, up to 25 m to either side and
    10 m below to 15 m above the line between them. Near a phone the spread shrinks to what
    its lens covers (``reach``: tangent of each phone's half field plus slack), so a zoomed
    phone does not make almost every draw a miss.
    """
    baseline = centre2 - centre1
    span = float(np.linalg.norm(baseline))
    side = np.cross(baseline, _UP)
    side /= np.linalg.norm(side)

    def draw() -> Array:
        along = rng.uniform(0.15, 0.85, count)
        extent = np.minimum(along * span * reach[0], (1.0 - along) * span * reach[1])
        lateral = rng.uniform(-1.0, 1.0, count) * np.minimum(25.0, extent)
        height = rng.uniform(np.maximum(-10.0, -extent), np.minimum(15.0, extent))
        return centre1 + along[:, None] * baseline + lateral[:, None] * side + height[:, None] * _UP

    return draw
