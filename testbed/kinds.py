"""Two-view scenes of several kinds, for testing how the solver ranks candidate geometries.

The solver is built for two phones facing each other, but people will also feed it pairs
that are nothing like that, and its ranking of geometries must not force the facing model
on them. Each kind here is a typical two-view set-up with its own epipolar geometry:

- ``venue``: the search for a friend itself (:func:`testbed.phones.phone_scene`): two phones 20-80 m
  apart aimed at each other; both epipoles inside both photos.
- ``room``: two fixed cameras high in two corners of a room, looking at its centre from
  60-120 degrees apart with wide lenses (surveillance, a room scanned from two tripods); the
  other camera is usually out of frame, so the epipoles are usually outside the photos.
- ``turntable``: one camera circling a small object at arm's length, two views 20-60 degrees
  apart (object scanning, the Middlebury temple); the epipoles are far outside the photos.
- ``street``: two people walking one behind the other, both photographing ahead; the
  baseline runs along the viewing direction, so an epipole lies in the photo as the focus
  of expansion although neither camera sees the other.

Every kind is a ``(rng, landmarks) -> Scene`` function, deterministic given the rng, that
redraws until ``landmarks`` points are in front of both cameras and inside both photos (2 %
margin). World coordinates are metres with y pointing down; pixels x right, y down.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from shared_solver.projective import Array
from testbed.phones import EDGE_MARGIN, aim, focal_pixels, intrinsics, phone_scene, photo_size
from testbed.scenes import Camera, Scene, seen_scene

_MAX_DRAWS = 200
ROOM_IMAGE_SIZE = (1920, 1080)
TURNTABLE_IMAGE_SIZES = ((1600, 1200), (640, 480))


def venue_scene(rng: np.random.Generator, landmarks: int) -> Scene:
    """Two phones facing each other across a venue (main cameras, no zoom)."""
    return phone_scene(rng, landmarks)


def room_scene(rng: np.random.Generator, landmarks: int) -> Scene:
    """Two fixed wide-angle cameras high in two adjacent corners of a room.

    The room is a (6-12 m) x (6-12 m) rectangle, floor at y = 0, redrawn until the two
    corners are 60-120 degrees apart as seen from its centre. Each camera hangs 2.5-3.5 m high
    just inside its corner and looks at the room's centre (1 m above the floor), with a
    16-24 mm (35 mm-equivalent) lens on a 1920 x 1080 px sensor. Landmarks: anywhere in the
    room from the floor to 2 m, seen by both.
    """
    size = ROOM_IMAGE_SIZE
    for _ in range(_MAX_DRAWS):
        width, depth = rng.uniform(6.0, 12.0, 2)
        # Adjacent corners (+-width/2, depth/2) are 2 atan(width/depth) apart around the centre.
        if not 60.0 <= math.degrees(2 * math.atan(width / depth)) <= 120.0:
            continue
        heights = rng.uniform(2.5, 3.5, 2)
        # 0.2 m in from the walls: a camera is mounted on them, not in them.
        centres = [
            np.array([sign * (width / 2 - 0.2), -height, depth / 2 - 0.2])
            for sign, height in zip((1.0, -1.0), heights, strict=True)
        ]
        target = np.array([0.0, -1.0, 0.0])
        cameras = [
            Camera(
                intrinsics(rng, focal_pixels(rng.uniform(16.0, 24.0), size), size),
                # Installed with care: a degree or so off, barely any roll.
                *aim(rng, centre, target, jitter_deg=1.0, roll_deg=1.0),
            )
            for centre in centres
        ]

        def draw(w: float = width, d: float = depth) -> Array:
            count = 4 * landmarks
            return np.column_stack(
                [
                    rng.uniform(-w / 2, w / 2, count),
                    -rng.uniform(0.0, 2.0, count),
                    rng.uniform(-d / 2, d / 2, count),
                ]
            )

        scene = seen_scene(draw, (cameras[0], cameras[1]), (size, size), landmarks, EDGE_MARGIN)
        if scene is not None:
            return scene
    raise RuntimeError("could not find a room both cameras see enough of")


def turntable_scene(rng: np.random.Generator, landmarks: int) -> Scene:
    """One camera circling a small object: two views 20-60 degrees apart on the circle.

    The object sits at the origin; the camera moves on a circle of radius 0.5-1.5 m at a
    fixed 10-40 degree elevation, aimed at the object, with a 35-70 mm (35 mm-equivalent) lens
    on a 1600 x 1200 or 640 x 480 px sensor, the same for both views (one camera). Landmarks:
    in a 0.3 m box around the object.
    """
    for _ in range(_MAX_DRAWS):
        size = TURNTABLE_IMAGE_SIZES[int(rng.integers(len(TURNTABLE_IMAGE_SIZES)))]
        k = intrinsics(rng, focal_pixels(rng.uniform(35.0, 70.0), size), size)
        radius = rng.uniform(0.5, 1.5)
        elevation = math.radians(rng.uniform(10.0, 40.0))
        start = rng.uniform(0.0, 2 * math.pi)
        azimuths = (start, start + math.radians(rng.uniform(20.0, 60.0)))
        cameras = [
            Camera(
                k,
                *aim(
                    rng,
                    radius
                    * np.array(
                        [
                            math.cos(elevation) * math.sin(azimuth),
                            -math.sin(elevation),
                            math.cos(elevation) * math.cos(azimuth),
                        ]
                    ),
                    np.zeros(3),
                    # A rig, not a hand: the object stays centred and the horizon level.
                    jitter_deg=0.5,
                    roll_deg=0.5,
                ),
            )
            for azimuth in azimuths
        ]

        def draw() -> Array:
            return rng.uniform(-0.15, 0.15, (4 * landmarks, 3))

        scene = seen_scene(draw, (cameras[0], cameras[1]), (size, size), landmarks, EDGE_MARGIN)
        if scene is not None:
            return scene
    raise RuntimeError("could not find turntable views that share the object")


def street_scene(rng: np.random.Generator, landmarks: int) -> Scene:
    """Two people walking down a street one behind the other, both photographing ahead.

    They stand 5-30 m apart along the street (either may lead) and up to 2 m apart across
    it, phones at eye level (1.4-1.8 m), each pointed roughly down the street (sd 8 degrees
    sideways, 3 degrees up-down and roll), main phone cameras in landscape or portrait.
    Landmarks: facades, signs and lamp posts 10-100 m ahead of the leading walker, up to
    20 m to either side and 0-25 m high.
    """
    for _ in range(_MAX_DRAWS):
        gap = rng.uniform(5.0, 30.0) * (1.0 if rng.random() < 0.5 else -1.0)
        eyes = rng.uniform(1.4, 1.8, 2)
        centres = [
            np.array([0.0, -eyes[0], 0.0]),
            np.array([rng.uniform(-2.0, 2.0), -eyes[1], gap]),
        ]
        sizes = (photo_size(rng), photo_size(rng))
        cameras = [
            Camera(
                intrinsics(rng, focal_pixels(26.0 * (1.0 + rng.normal(0.0, 0.05)), size), size),
                # Aimed at the horizon straight down the street, then off by hand.
                *aim(
                    rng,
                    centre,
                    centre + np.array([0.0, 0.0, 100.0]),
                    jitter_deg=8.0,
                    roll_deg=3.0,
                ),
            )
            for centre, size in zip(centres, sizes, strict=True)
        ]
        lead = max(0.0, gap)

        def draw(lead: float = lead) -> Array:
            count = 4 * landmarks
            ahead = rng.uniform(10.0, 100.0, count)
            # Near the walkers the lens covers only a few metres sideways: no wasted draws.
            across = rng.uniform(-1.0, 1.0, count) * np.minimum(20.0, 0.8 * ahead)
            return np.column_stack([across, -rng.uniform(0.0, 25.0, count), lead + ahead])

        scene = seen_scene(draw, (cameras[0], cameras[1]), sizes, landmarks, EDGE_MARGIN)
        if scene is not None:
            return scene
    raise RuntimeError("could not find a street view both walkers share")


SCENE_KINDS: dict[str, Callable[[np.random.Generator, int], Scene]] = {
    "venue": venue_scene,
    "room": room_scene,
    "turntable": turntable_scene,
    "street": street_scene,
}
"""Scene generators by kind: ``SCENE_KINDS[kind](rng, landmarks) -> Scene``."""
