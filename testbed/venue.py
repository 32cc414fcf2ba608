"""Rendered photo pairs of a hall seen from both ends, with everything about them known.

``rendered_pair(seed)`` places two phones as :func:`testbed.phones.phone_scene` does (12 MP,
26 mm, 20-80 m apart, each aimed by hand at the other), builds a hall around them
(:mod:`testbed.hall`), renders both photos at the size the server stores (long side 2560
px) and makes them look taken: exposure and white balance of each phone, vignetting, a
little blur, sensor noise, JPEG at the server's quality. The landmarks are the hall's
salient spots (poster corners, line crossings, section signs, lamps) that both photos
show, unoccluded and inside the frame; the true cameras, so the true fundamental matrix,
come with them. Spots one photo shows and the other does not are kept too: a search for
them must come back empty.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from shared_solver.matching import Epipolar
from shared_solver.projective import Array, Indices, Mask

from .arena import Arena, build_arena
from .hall import build_hall
from .phones import EDGE_MARGIN, phone_scene
from .render import Surface, lit, render
from .scenes import Camera, Scene, in_photo
from .textures import Image

STORED_SIDE = 2560  # backend/settings.py stored_photo_side: the photos the server keeps
JPEG_QUALITY = 90  # backend/photos.py: the quality photos are stored at
# A spot counts as seen when no surface in front of it is nearer by more than this
# fraction of its depth (the depth buffer is sampled at the nearest pixel).
_DEPTH_TOLERANCE = 0.01


@dataclass(frozen=True)
class RenderedPair:
    """Two rendered photos of one hall and the truth about them.

    Attributes:
        photo1, photo2: (H, W, 3) uint8 BGR photos as the server stores them.
        scene: both cameras (intrinsics at the stored size) and ``points``, the (N, 3)
            landmarks both photos show; ``scene.landmarks1``/``2`` are their pixels,
            ``scene.fundamental`` the true F, ``scene.epipole1``/``2`` the friends.
        normals: (N, 3) unit normal of the surface each landmark lies on.
        kinds: what each landmark lies on ("floor", "stand", "wall", "boards", "roof",
            "pillar", "equipment", "stage", "scoreboard").
        only1, only2: (M, 3) salient spots that photo 1 (2) shows and the other does not
            (hidden behind something, facing away, or outside the frame).
    """

    photo1: Image
    photo2: Image
    scene: Scene
    normals: Array
    kinds: tuple[str, ...]
    only1: Array
    only2: Array


def stored_camera(camera: Camera, size: tuple[int, int]) -> tuple[Camera, tuple[int, int]]:
    """The camera and photo size after the server's downscale to ``STORED_SIDE`` px."""
    scale = STORED_SIDE / max(size)
    shrink = np.diag([scale, scale, 1.0])
    stored = (round(size[0] * scale), round(size[1] * scale))
    return Camera(shrink @ camera.intrinsics, camera.rotation, camera.translation), stored


def rendered_pair(seed: int | Sequence[int], *, max_landmarks: int = 400) -> RenderedPair:
    """Both photos of a hall, deterministic for the seed (module docstring).

    Args:
        seed: the seed of every random choice (the phones, the hall, the textures, the
            photos' effects): an int or a sequence of ints (``numpy.random.default_rng``).
        max_landmarks: at most this many landmarks (and spots seen by one photo only) are
            kept, drawn at random from those found.
    """

    def hall(rng: np.random.Generator, camera1: Camera, camera2: Camera) -> Arena:
        surfaces = build_hall(rng, camera1, camera2)
        return Arena(surfaces, surfaces, [], [])

    return _rendered(np.random.default_rng(seed), hall, max_landmarks)


def rendered_arena(seed: int | Sequence[int], *, max_landmarks: int = 400) -> RenderedPair:
    """Both photos of an arena full of look-alikes (:mod:`testbed.arena`: banners seen
    from both sides, mats, signs and posters alike, pillars alike, a video board, moving
    spotlights), as :func:`rendered_pair` renders a hall."""
    return _rendered(np.random.default_rng(seed), build_arena, max_landmarks)


def _rendered(
    rng: np.random.Generator,
    build: Callable[[np.random.Generator, Camera, Camera], Arena],
    max_landmarks: int,
) -> RenderedPair:
    phones = phone_scene(rng, 4)
    camera1, size1 = stored_camera(phones.camera1, phones.image_size1)
    camera2, size2 = stored_camera(phones.camera2, phones.image_size2)
    venue = build(rng, camera1, camera2)
    radiance1, depth1 = render(venue.surfaces1, camera1, size1)
    radiance2, depth2 = render(venue.surfaces2, camera2, size2)
    radiance1 = lit(radiance1, depth1, camera1, venue.lights1)
    radiance2 = lit(radiance2, depth2, camera2, venue.lights2)
    spots, normals, kinds, inner, two_sided = _salient(venue.surfaces1)
    seen1 = _seen(spots, normals, two_sided, camera=camera1, size=size1, inverse_depth=depth1)
    seen2 = _seen(spots, normals, two_sided, camera=camera2, size=size2, inverse_depth=depth2)

    def pick(mask: Mask) -> Indices:
        chosen = np.flatnonzero(mask)
        if len(chosen) > max_landmarks:
            chosen = np.sort(rng.choice(chosen, max_landmarks, replace=False))
        return chosen

    # A spot on the edge of its surface may be the corner of a box: the other photo can
    # show it on the face next to it, so it is no spot of one photo only.
    both = pick(seen1 & seen2)
    only1, only2 = pick(seen1 & ~seen2 & inner), pick(seen2 & ~seen1 & inner)
    return RenderedPair(
        photograph(rng, radiance1),
        photograph(rng, radiance2),
        Scene(camera1, camera2, spots[both], size1, size2),
        normals[both],
        tuple(kinds[i] for i in both),
        spots[only1],
        spots[only2],
    )


def photograph(rng: np.random.Generator, radiance: Array) -> Image:
    """What a phone makes of the light: its exposure and white balance, vignetting, a
    slightly soft lens, sensor noise, and the stored JPEG."""
    height, width = radiance.shape[:2]
    gain = rng.uniform(0.75, 1.25) * rng.uniform(0.93, 1.07, 3)
    ys, xs = np.ogrid[:height, :width]
    radius2 = ((xs - width / 2) ** 2 + (ys - height / 2) ** 2) / (0.25 * (width**2 + height**2))
    falloff = (1.0 - rng.uniform(0.15, 0.35) * radius2).astype(np.float32)
    noise_sd = rng.uniform(1.5, 4.0)
    blur = rng.uniform(0.5, 1.0)
    channels = []
    for channel, value in zip(cv2.split(radiance), gain, strict=True):
        exposed = cv2.GaussianBlur(channel * falloff, (0, 0), blur)
        noise = rng.standard_normal(exposed.shape, dtype=np.float32)
        # OpenCV saturates to 0-255 as it converts, like a sensor clipping.
        channels.append(cv2.addWeighted(exposed, value, noise, noise_sd, 0.0, dtype=cv2.CV_8U))
    photo = cv2.merge(channels)
    ok, jpeg = cv2.imencode(".jpg", photo, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
    assert ok
    return np.asarray(cv2.imdecode(jpeg, cv2.IMREAD_COLOR), dtype=np.uint8)


def _salient(surfaces: list[Surface]) -> tuple[Array, Array, list[str], Mask, Mask]:
    """(K, 3) world points of every surface's salient texels, (K, 3) the normal of the
    surface each lies on, that surface's kind, (K,) whether the point is off its
    surface's edges (by more than a texel), and (K,) whether its surface is seen from both
    sides."""
    points, normals, kinds, inner, two_sided = [], [], [], [], []
    for surface in surfaces:
        salient = surface.texture.salient
        if len(salient):
            height, width = surface.shape
            # A texel index to its centre, kept on the plane: a corner texel's centre is
            # half a texel inside the edge, its index + 1 half a texel outside.
            plane = np.clip(salient + 0.5, 0.0, [width, height])
            points.append(surface.world(plane))
            normals.append(np.broadcast_to(surface.normal, (len(salient), 3)))
            kinds += [surface.kind] * len(salient)
            inner.append(((plane > 1.0) & (plane < [width - 1.0, height - 1.0])).all(axis=1))
            two_sided.append(np.full(len(salient), surface.two_sided))
    return (
        np.vstack(points),
        np.vstack(normals),
        kinds,
        np.concatenate(inner),
        np.concatenate(two_sided),
    )


def _seen(
    points: Array,
    normals: Array,
    two_sided: Mask,
    *,
    camera: Camera,
    size: tuple[int, int],
    inverse_depth: Array,
) -> Mask:
    """(K,) which points the camera shows: inside the frame with the usual margin, on a
    side of their surface that is drawn and faces it, their own surface drawn at or next
    to their pixel and nothing nearer around it (3 x 3 pixels: a corner on a silhouette is
    seen, one that something passes in front of is not)."""
    inside = in_photo(camera, points, size, EDGE_MARGIN)
    facing = two_sided | (np.einsum("ki,ki->k", normals, camera.centre - points) > 0)
    seen = inside & facing
    pixels = np.round(camera.project(points[seen])).astype(int)
    own = 1.0 / camera.depth(points[seen])
    offsets = np.arange(-1, 2)
    rows = pixels[:, 1, None, None] + offsets[None, :, None]
    cols = pixels[:, 0, None, None] + offsets[None, None, :]
    around = inverse_depth[rows, cols].reshape(len(own), -1)
    nothing_nearer = around.max(axis=1) <= own * (1.0 + _DEPTH_TOLERANCE)
    drawn = (np.abs(around - own[:, None]) <= _DEPTH_TOLERANCE * own[:, None]).any(axis=1)
    seen[np.flatnonzero(seen)] = nothing_nearer & drawn
    return seen


def diagonal(size: tuple[int, int]) -> float:
    return math.hypot(*size)


def good_answer(scene: Scene) -> Epipolar:
    """The true F, with a round uncertainty that moves a line by about 2 px, oriented by the
    scene's landmarks."""
    f = scene.fundamental
    lines = np.column_stack([scene.landmarks1, np.ones(len(scene.points))]) @ f.T
    spread = float(np.median(np.hypot(lines[:, 0], lines[:, 1])))
    typical = 2.0 * spread / max(scene.image_size1) ** 2
    return Epipolar(f, typical**2 * np.eye(9)).oriented(scene.landmarks1, scene.landmarks2)
