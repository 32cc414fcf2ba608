"""Prints of an arena that look alike from where the other friend stands.

The suggestion looks for a landmark's patch along a band of the other photo; what fools it
is a print that looks the same somewhere else on that band (docs/suggestions.md):

- a **banner** hung across the hall is seen from the front by one phone and from the back
  by the other. A mesh banner shows its print through, mirrored from behind; a banner
  printed on both sides reads right from each, so the corner one phone sees on the left
  the other sees on the right, and the same design's corner from behind is another corner;
- a **mat** on the floor is seen turned 180 degrees from the other end: its print is
  symmetric under that turn, so each of its corners looks like the opposite one;
- **signs** and **posters** repeat the same design along a wall, at one height: all on one
  epipolar line when the wall runs between the phones;
- a **video board** shows something else in each photo; only its frame stays.

Each maker returns a :class:`~testbed.textures.Texture` whose salient texels are those a
person would tap (the corners of the print, of its panel, of the mat's border).
"""

from __future__ import annotations

import cv2
import numpy as np

from .textures import Image, Texture, grain, poster, random_colour, tinted


def corners(x0: int, y0: int, x1: int, y1: int) -> list[tuple[int, int]]:
    """The four corners of a box, clockwise from the top left."""
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def banner(rng: np.random.Generator, shape: tuple[int, int], texels_per_metre: float) -> Texture:
    """A sponsor's banner: a coloured ground, a framed panel with a logo and letters. Its
    salient texels: the banner's four corners first, then the panel's four."""
    height, width = shape
    image = poster(rng, shape)
    inset = max(3, int(0.15 * texels_per_metre))
    x0, y0 = inset, inset
    x1 = int(rng.uniform(0.35, 0.6) * width)
    y1 = height - inset
    image[y0:y1, x0:x1] = poster(rng, (y1 - y0, x1 - x0))
    cv2.rectangle(image, (x0, y0), (x1, y1), random_colour(rng, 0, 255), max(2, inset // 3))
    salient = corners(0, 0, width, height) + corners(x0, y0, x1, y1)
    return Texture(image, np.array(salient, dtype=float))


def mat(rng: np.random.Generator, shape: tuple[int, int], texels_per_metre: float) -> Texture:
    """A floor mat whose print is the same turned 180 degrees: a border, and a design whose
    lower half is its upper half turned. Salient: its corners and its border's inner
    corners."""
    height, width = shape
    ground = np.array(random_colour(rng, 20, 200), dtype=float)
    image = tinted(ground, 6.0 * grain(rng, shape, (12.0, 3.0)))
    half = image[: height // 2]
    for _ in range(int(rng.integers(2, 5))):
        colour = random_colour(rng, 0, 255)
        centre = (int(rng.integers(0, width)), int(rng.integers(0, height // 2)))
        radius = int(rng.uniform(0.1, 0.3) * height)
        cv2.circle(half, centre, radius, colour, -1, cv2.LINE_AA)
    image[height - height // 2 :] = half[::-1, ::-1]
    border = max(3, int(0.12 * texels_per_metre))
    colour = random_colour(rng, 0, 255)
    cv2.rectangle(image, (0, 0), (width - 1, height - 1), colour, 2 * border)
    inner = corners(border, border, width - border, height - border)
    return Texture(image, np.array(corners(0, 0, width, height) + inner, dtype=float))


def sign(rng: np.random.Generator, shape: tuple[int, int]) -> Texture:
    """A sign of a few letters and an arrow on a bright ground (an exit, a gate); its
    corners are salient."""
    height, width = shape
    image = np.empty((height, width, 3), np.uint8)
    image[:] = random_colour(rng, 60, 255)
    ink = random_colour(rng, 0, 80) if image[0, 0].mean() > 128 else (245, 245, 245)
    thick = max(2, height // 12)
    cv2.putText(
        image,
        str(rng.choice(["EXIT", "GATE", "WC", "BAR", "A12"])),
        (width // 12, int(0.75 * height)),
        cv2.FONT_HERSHEY_DUPLEX,
        height / 40.0,
        ink,
        thick,
        cv2.LINE_AA,
    )
    tip = (int(0.92 * width), height // 2)
    cv2.arrowedLine(image, (int(0.65 * width), height // 2), tip, ink, thick, cv2.LINE_AA)
    return Texture(image, np.array(corners(0, 0, width, height), dtype=float))


def video_board(
    rng: np.random.Generator, shape: tuple[int, int], frame: tuple[int, ...], thick: int
) -> Texture:
    """A video board: a fixed frame (``frame`` BGR, ``thick`` texels) around whatever it
    shows at the moment (a new poster for each call). Its frame's corners are salient."""
    height, width = shape
    image = poster(rng, shape)
    cv2.rectangle(image, (0, 0), (width - 1, height - 1), frame, 2 * thick)
    return Texture(image, np.array(corners(0, 0, width, height), dtype=float))


def mirrored(image: Image) -> Image:
    """The print as the back of a banner printed to read from both sides carries it, on the
    front's texel grid."""
    return np.ascontiguousarray(image[:, ::-1])
