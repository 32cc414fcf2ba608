"""Render textured planes into a pinhole camera: one homography per tile, a depth buffer.

A plane's texture maps to the photo by a homography (Hartley & Zisserman 2.3), so
``cv2.warpPerspective`` draws it exactly. Two things make that a photo rather than a
smear:

- **Tiles and mip levels.** A floor runs from a few metres to eighty: near the camera a
  texel covers many pixels, far away many texels fall in one. Each tile of the texture is
  drawn from the level of its image pyramid whose texels are about one pixel there, so
  distant texture is averaged (as a lens does) instead of aliased.
- **Occlusion.** The inverse depth of a plane is an affine function of the pixel, so the
  depth buffer costs one multiply-add per pixel and tile; the nearest plane wins.

Tiles are clipped against a near plane in front of the camera first: a plane that runs
behind the camera would otherwise fold back into the photo through infinity.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import cv2
import numpy as np

from shared_solver.projective import Array

from .scenes import Camera
from .textures import Image, Texture

TILE = 256  # texels per tile side
_NEAR = 0.3  # m in front of the camera: what is nearer is not drawn
_MARGIN = 2  # texels around a tile, so bilinear interpolation has neighbours at its edges
_SUBPIXEL_BITS = 4  # fillPoly's fixed-point precision


@dataclass(frozen=True)
class Surface:
    """A textured rectangle in the world, seen from the side its normal points to.

    Plane position (s, t) in texels (texel index (i, j) covers ``[i, i + 1) x [j, j + 1)``,
    its centre at (i + 0.5, j + 0.5)) is the world point
    ``origin + s / W * across + t / H * down`` for a texture of W x H texels: looked at from
    the front, ``across`` runs right and ``down`` runs down, so text reads as drawn.

    A hanging banner is seen from both sides: ``back`` is what its other side shows, on the
    same texel grid (texel (s, t) of ``back`` is at the same world point as that of
    ``texture``). A print that shows through (a mesh banner) has ``back`` equal to
    ``texture`` and reads mirrored from behind; a banner printed on both sides to read
    from each has ``back`` the mirror image of ``texture``.
    """

    origin: Array  # (3,) m
    across: Array  # (3,) m, the texture's full width
    down: Array  # (3,) m, the texture's full height
    texture: Texture
    kind: str = ""  # what it is ("floor", "stand", ...), for reports
    back: Image | None = None  # the other side's print, when seen from both sides

    @property
    def normal(self) -> Array:
        """(3,) unit normal of the drawn side (towards a camera that sees it)."""
        n = np.cross(self.down, self.across)
        return n / np.linalg.norm(n)

    @property
    def shape(self) -> tuple[int, int]:
        """(H, W) texels."""
        return self.texture.image.shape[0], self.texture.image.shape[1]

    def world(self, texels: Array) -> Array:
        """(N, 3) world points of (N, 2) plane positions (s, t) in texels."""
        height, width = self.shape
        return (
            self.origin
            + texels[:, :1] / width * self.across[None]
            + texels[:, 1:] / height * self.down[None]
        )

    def faces(self, camera: Camera) -> bool:
        """Whether the camera is on the drawn side (the front)."""
        return bool(self.normal @ (camera.centre - self.origin) > 0)

    @property
    def two_sided(self) -> bool:
        return self.back is not None

    @functools.cached_property
    def pyramid(self) -> list[Image]:
        """The texture and its halvings (``cv2.pyrDown``), down to a few texels."""
        return _pyramid(self.texture.image)

    @functools.cached_property
    def back_pyramid(self) -> list[Image]:
        """The same for the back (empty for a surface drawn on one side)."""
        return [] if self.back is None else _pyramid(self.back)


def _pyramid(image: Image) -> list[Image]:
    levels = [image]
    while min(levels[-1].shape[:2]) > 8:
        levels.append(np.asarray(cv2.pyrDown(levels[-1]), dtype=np.uint8))
    return levels


def texel_homography(surface: Surface, camera: Camera) -> Array:
    """(3, 3) homography from texel (s, t, 1) to the camera's homogeneous pixel."""
    height, width = surface.shape
    rotation = camera.rotation
    columns = np.column_stack(
        [
            rotation @ surface.across / width,
            rotation @ surface.down / height,
            rotation @ surface.origin + camera.translation,
        ]
    )
    return camera.intrinsics @ columns


def inverse_depth_plane(surface: Surface, camera: Camera) -> Array:
    """(3,) coefficients (a, b, c): ``1 / depth = a x + b y + c`` at pixel (x, y) on the
    plane (depth along the optical axis, m)."""
    normal = camera.rotation @ surface.normal
    offset = normal @ (camera.rotation @ surface.origin + camera.translation)
    return (normal @ np.linalg.inv(camera.intrinsics)) / offset


def render(surfaces: list[Surface], camera: Camera, size: tuple[int, int]) -> tuple[Array, Array]:
    """The planes as ``camera`` sees them, without lens or sensor effects.

    Args:
        surfaces: every plane of the scene.
        camera: the camera; ``size`` (width, height) px its photo.

    Returns:
        (H, W, 3) float32 BGR in 0-255, and (H, W) float64 inverse depth (1/m; 0 where no
        plane is seen).
    """
    width, height = size
    image = np.zeros((height, width, 3), np.float32)
    inverse_depth = np.zeros((height, width))
    for surface in surfaces:
        front = surface.faces(camera)
        if not front and not surface.two_sided:
            continue
        seen = _Seen(
            surface,
            camera,
            texel_homography(surface, camera),
            inverse_depth_plane(surface, camera),
            surface.pyramid if front else surface.back_pyramid,
        )
        rows, cols = surface.shape
        for t0 in range(0, rows, TILE):
            for s0 in range(0, cols, TILE):
                box = (s0, t0, min(cols, s0 + TILE), min(rows, t0 + TILE))
                _draw_tile(seen, box, image, inverse_depth)
    return image, inverse_depth


@dataclass(frozen=True)
class _Seen:
    """A surface as one camera sees it: texel -> pixel homography, inverse-depth plane,
    and the pyramid of the side it sees."""

    surface: Surface
    camera: Camera
    homography: Array
    plane: Array
    pyramid: list[Image]


def _draw_tile(
    seen: _Seen, box: tuple[int, int, int, int], image: Array, inverse_depth: Array
) -> None:
    """Draw one tile of the surface (texels ``box``: s0, t0, s1, t1) where it is nearer
    than what ``inverse_depth`` holds, and record its inverse depth there."""
    surface, camera, homography, plane = seen.surface, seen.camera, seen.homography, seen.plane
    s0, t0, s1, t1 = box
    corners = np.array([[s0, t0], [s1, t0], [s1, t1], [s0, t1]], dtype=float)
    polygon = _clip_near(camera, surface.world(corners))
    if len(polygon) < 3:
        return
    pixels = camera.project(polygon)
    height, width = inverse_depth.shape
    # Far outside the photo a projected corner can be huge: clamp before rounding.
    pixels = np.clip(pixels, -4 * width, 5 * width)
    x0, y0 = np.floor(pixels.min(axis=0)).astype(int)
    x1, y1 = np.ceil(pixels.max(axis=0)).astype(int) + 1
    x0, y0, x1, y1 = max(x0, 0), max(y0, 0), min(x1, width), min(y1, height)
    if x1 <= x0 or y1 <= y0:
        return
    level = _mip_level(homography, pixels, len(seen.pyramid) - 1)
    scale = 2.0**level
    # Level-L texel index u is plane position 2^L (u + 0.5) in level-0 texels (pyrDown
    # averages texels 2u and 2u + 1, whose centres are at 2u + 0.5 and 2u + 1.5).
    texels = seen.pyramid[level]
    u0 = max(0, int(s0 / scale) - _MARGIN)
    v0 = max(0, int(t0 / scale) - _MARGIN)
    u1 = min(texels.shape[1], math.ceil(s1 / scale) + _MARGIN)
    v1 = min(texels.shape[0], math.ceil(t1 / scale) + _MARGIN)
    to_level0 = np.array(
        [[scale, 0.0, scale * (u0 + 0.5)], [0.0, scale, scale * (v0 + 0.5)], [0.0, 0.0, 1.0]]
    )
    to_roi = np.array([[1.0, 0.0, -x0], [0.0, 1.0, -y0], [0.0, 0.0, 1.0]])
    warp = to_roi @ homography @ to_level0
    roi_w, roi_h = x1 - x0, y1 - y0
    drawn = cv2.warpPerspective(
        texels[v0:v1, u0:u1],
        warp,
        (roi_w, roi_h),
        flags=cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_REPLICATE,
    )
    mask = np.zeros((roi_h, roi_w), np.uint8)
    points = np.round((pixels - [x0, y0]) * (1 << _SUBPIXEL_BITS)).astype(np.int32)
    cv2.fillPoly(mask, [points], 1, cv2.LINE_8, _SUBPIXEL_BITS)
    xs = np.arange(x0, x1, dtype=float)
    ys = np.arange(y0, y1, dtype=float)
    depth = plane[0] * xs[None, :] + plane[1] * ys[:, None] + plane[2]
    buffer = inverse_depth[y0:y1, x0:x1]
    nearer = (mask > 0) & (depth > buffer)
    image[y0:y1, x0:x1][nearer] = drawn[nearer]
    buffer[nearer] = depth[nearer]


def _mip_level(homography: Array, pixels: Array, deepest: int) -> int:
    """The pyramid level whose texels are about one pixel at the tile's centre: the
    homography's local area scale gives pixels per texel."""
    centre = pixels.mean(axis=0)
    inverse = np.linalg.inv(homography)
    point = inverse @ np.array([centre[0], centre[1], 1.0])
    s, t = point[:2] / point[2]
    mapped = homography @ np.array([s, t, 1.0])
    w = mapped[2]
    # The Jacobian of (s, t) -> pixel is (H[:2, :2] w - xy H[2, :2]) / w^2.
    jacobian = (homography[:2, :2] * w - np.outer(mapped[:2], homography[2, :2])) / w**2
    pixels_per_texel = math.sqrt(abs(float(np.linalg.det(jacobian))))
    if pixels_per_texel <= 0:
        return deepest
    return int(np.clip(math.floor(math.log2(1.0 / pixels_per_texel)), 0, deepest))


def _clip_near(camera: Camera, polygon: Array) -> Array:
    """(M, 3) the part of the convex world polygon (N, 3) at least ``_NEAR`` in front of
    the camera (Sutherland-Hodgman against one plane)."""
    depth = camera.depth(polygon) - _NEAR
    kept = []
    for index in range(len(polygon)):
        a, b = polygon[index], polygon[(index + 1) % len(polygon)]
        da, db = depth[index], depth[(index + 1) % len(polygon)]
        if da >= 0:
            kept.append(a)
        if (da >= 0) != (db >= 0):
            kept.append(a + (b - a) * (da / (da - db)))
    return np.array(kept).reshape(-1, 3)


@dataclass(frozen=True)
class Light:
    """A pool of light a spotlight throws on the scene: brighter by ``gain`` (a fraction)
    at ``centre`` (3,) m, falling off as a Gaussian of sd ``radius`` m. Spotlights move
    between two photos taken seconds apart, so each photo has its own."""

    centre: Array
    radius: float
    gain: float


def lit(radiance: Array, inverse_depth: Array, camera: Camera, lights: list[Light]) -> Array:
    """(H, W, 3) float32: ``radiance`` under the pools of ``lights``, each pixel by the
    world point it shows (from ``inverse_depth``, as :func:`render` returns it)."""
    if not lights:
        return radiance
    height, width = inverse_depth.shape
    xs, ys = np.meshgrid(np.arange(width, dtype=np.float32), np.arange(height, dtype=np.float32))
    # A pixel's ray R^T K^-1 (x, y, 1) has depth 1 along the optical axis.
    rays = np.linalg.inv(camera.intrinsics).astype(np.float32)
    depth = np.where(inverse_depth > 0, 1.0 / np.maximum(inverse_depth, 1e-9), 0.0)
    depth = depth.astype(np.float32)
    camera_frame = [(rays[i, 0] * xs + rays[i, 1] * ys + rays[i, 2]) * depth for i in range(3)]
    gain = np.ones((height, width), np.float32)
    centre = camera.centre
    for light in lights:
        # The light's centre in the camera's frame, so the world point needs no rotation.
        target = camera.rotation @ (light.centre - centre)
        distance2 = sum((camera_frame[i] - np.float32(target[i])) ** 2 for i in range(3))
        gain += np.float32(light.gain) * np.exp(distance2 * np.float32(-0.5 / light.radius**2))
    gain[inverse_depth <= 0] = 1.0
    return radiance * gain[:, :, None]
