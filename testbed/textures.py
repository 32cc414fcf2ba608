"""Procedural textures of a hall's surfaces: OpenCV drawing and numpy noise, nothing downloaded.

Each maker returns a :class:`Texture`: a BGR image whose texels have a known size in metres,
and the texels people would tap as landmarks (a poster's corner, a line crossing on the
floor, the end of a row, a lamp). Everything is drawn from the caller's random generator, so
a hall is the same for the same seed.
"""

from __future__ import annotations

import string
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from shared_solver.projective import Array

Image = NDArray[np.uint8]
_LETTERS = string.ascii_uppercase + string.digits
_FONTS = (cv2.FONT_HERSHEY_SIMPLEX, cv2.FONT_HERSHEY_DUPLEX, cv2.FONT_HERSHEY_TRIPLEX)


@dataclass(frozen=True)
class Texture:
    """An image to paint on a plane, and where on it a person would tap.

    Attributes:
        image: (H, W, 3) uint8 BGR; texel (column s, row t) covers
            ``[s, s + 1) x [t, t + 1)`` of the plane in units of ``metres_per_texel``.
        salient: (K, 2) texel indices (column, row) of spots worth tapping.
    """

    image: Image
    salient: Array


def smooth_noise(rng: np.random.Generator, shape: tuple[int, int], cell: float) -> Array:
    """(H, W) float32 noise of unit sd, smooth over about ``cell`` texels (a random grid
    enlarged by bicubic interpolation: cheap at any size)."""
    rows = max(2, int(shape[0] / cell) + 2)
    cols = max(2, int(shape[1] / cell) + 2)
    grid = rng.normal(0.0, 1.0, (rows, cols)).astype(np.float32)
    enlarged = cv2.resize(grid, (shape[1], shape[0]), interpolation=cv2.INTER_CUBIC)
    return np.asarray(enlarged, dtype=np.float32)


def grain(rng: np.random.Generator, shape: tuple[int, int], cells: tuple[float, ...]) -> Array:
    """(H, W) float32 sum of smooth noise at several scales, the finer ones weaker."""
    total = np.zeros(shape, np.float32)
    for index, cell in enumerate(cells):
        total += smooth_noise(rng, shape, cell) / (1.0 + index)
    return total


def tinted(base: Array, shade: Array) -> Image:
    """(H, W, 3) uint8 of a BGR colour ``base`` (3,) modulated by ``shade`` (H, W) float32 in
    0-255 units, clipped to 0-255."""
    channels = [np.clip(shade + np.float32(value), 0, 255).astype(np.uint8) for value in base]
    return np.asarray(cv2.merge(channels), dtype=np.uint8)


def random_colour(rng: np.random.Generator, low: int = 30, high: int = 230) -> tuple[int, ...]:
    return tuple(int(c) for c in rng.integers(low, high, 3))


def random_word(rng: np.random.Generator, length: int) -> str:
    return "".join(rng.choice(list(_LETTERS), length))


def concrete(rng: np.random.Generator, shape: tuple[int, int], panel: int) -> Texture:
    """A painted wall: grey-brown noise, panel seams every ``panel`` texels, a few stains."""
    base = np.array([rng.uniform(90, 170)] * 3) + rng.normal(0, 12, 3)
    image = tinted(base, 14.0 * grain(rng, shape, (60.0, 12.0, 3.0)))
    height, width = shape
    for x in range(panel, width, panel):
        cv2.line(image, (x, 0), (x, height - 1), (40, 40, 40), 2)
    for _ in range(int(width * height / 40000)):
        centre = (int(rng.integers(0, width)), int(rng.integers(0, height)))
        axes = (int(rng.integers(5, 40)), int(rng.integers(5, 25)))
        shade = tuple(int(c) for c in np.clip(base + rng.normal(-25, 10, 3), 0, 255))
        cv2.ellipse(image, centre, axes, float(rng.uniform(0, 180)), 0, 360, shade, -1)
    return Texture(image, np.zeros((0, 2)))


def poster(rng: np.random.Generator, shape: tuple[int, int]) -> Image:
    """An advertising poster or sign: a coloured ground, a shape or two, lines of letters."""
    height, width = shape
    image = np.empty((height, width, 3), np.uint8)
    image[:] = random_colour(rng)
    for _ in range(int(rng.integers(1, 4))):
        colour = random_colour(rng)
        centre = (int(rng.integers(0, width)), int(rng.integers(0, height)))
        if rng.random() < 0.5:
            radius = int(rng.integers(max(2, height // 8), max(3, height // 2)))
            cv2.circle(image, centre, radius, colour, -1, cv2.LINE_AA)
        else:
            corner = (int(rng.integers(0, width)), int(rng.integers(0, height)))
            cv2.rectangle(image, centre, corner, colour, -1)
    lines = int(rng.integers(1, 4))
    for line in range(lines):
        scale = rng.uniform(0.5, 1.0) * height / (30.0 * lines)
        thickness = max(1, int(scale * 2))
        text = random_word(rng, int(rng.integers(3, 9)))
        x = int(rng.uniform(0.02, 0.3) * width)
        y = int((line + 0.8) * height / lines)
        cv2.putText(
            image,
            text,
            (x, y),
            rng.choice(_FONTS),
            scale,
            random_colour(rng),
            thickness,
            cv2.LINE_AA,
        )
    cv2.rectangle(image, (0, 0), (width - 1, height - 1), random_colour(rng, 0, 80), 2)
    return image


def wall_with_posters(
    rng: np.random.Generator, shape: tuple[int, int], texels_per_metre: float
) -> Texture:
    """A wall with posters and signs hung at eye height and above; their corners are
    salient."""
    wall = concrete(rng, shape, panel=int(rng.uniform(3, 6) * texels_per_metre))
    image = wall.image
    height, width = shape
    salient = []
    x = rng.uniform(1.0, 4.0) * texels_per_metre
    while x < width - texels_per_metre:
        w = int(rng.uniform(1.0, 4.0) * texels_per_metre)
        h = int(rng.uniform(0.6, 2.5) * texels_per_metre)
        y = int(rng.uniform(0.1, 0.7) * height)
        x0 = int(x)
        if x0 + w < width and y + h < height:
            image[y : y + h, x0 : x0 + w] = poster(rng, (h, w))
            salient += [(x0, y), (x0 + w, y), (x0, y + h), (x0 + w, y + h)]
        x += w + rng.uniform(1.0, 8.0) * texels_per_metre
    return Texture(image, np.array(salient, dtype=float).reshape(-1, 2))


def seating(rng: np.random.Generator, shape: tuple[int, int], texels_per_metre: float) -> Texture:
    """Stands seen from the hall: rows of seats (one row every ~0.8 m up the slope), people
    in most of them, stairs every few metres with a section sign at the bottom of each.

    Rows run along the texture's width; row 0 is the top (back) row. The repeated rows are
    the hard part of finding a spot again, as in a real stadium.
    """
    height, width = shape
    seat_colour = np.array(random_colour(rng, 40, 200), dtype=float)
    row_pitch = 0.8 * texels_per_metre
    seat_pitch = 0.5 * texels_per_metre
    image = tinted(np.array([70.0, 70.0, 75.0]), 10.0 * grain(rng, shape, (30.0, 6.0)))
    aisle_every = int(rng.integers(12, 30))
    salient = []
    row_top = 0.0
    while row_top + row_pitch <= height:
        top, bottom = int(row_top + 0.15 * row_pitch), int(row_top + row_pitch)
        cv2.line(image, (0, int(row_top)), (width - 1, int(row_top)), (35, 35, 35), 2)
        column = 0
        x = 0.0
        while x + seat_pitch <= width:
            left, right = int(x + 1), int(x + seat_pitch - 1)
            if column % aisle_every == 0:
                # A stair: pale steps, no seat.
                cv2.rectangle(image, (left, top), (right, bottom), (150, 150, 145), -1)
            else:
                shade = seat_colour + rng.normal(0, 8, 3)
                cv2.rectangle(image, (left, top), (right, bottom), shade.tolist(), -1)
                if rng.random() < 0.7:
                    _person(rng, image, (left, top, right, bottom))
            column += 1
            x += seat_pitch
        row_top += row_pitch
    # Section signs at the foot of each stair: "112", "113", ...; their corners are salient.
    section = int(rng.integers(100, 400))
    sign_h = int(0.5 * texels_per_metre)
    sign_w = int(1.2 * texels_per_metre)
    for column in range(0, int(width / seat_pitch), aisle_every):
        x0 = int(column * seat_pitch - sign_w / 2 + seat_pitch / 2)
        y0 = height - sign_h - 2
        if x0 < 0 or x0 + sign_w >= width:
            continue
        colour = random_colour(rng, 120, 255)
        cv2.rectangle(image, (x0, y0), (x0 + sign_w, y0 + sign_h), colour, -1)
        cv2.putText(
            image,
            str(section),
            (x0 + sign_w // 8, y0 + int(sign_h * 0.8)),
            _FONTS[0],
            sign_h / 30.0,
            (20, 20, 20),
            max(1, sign_h // 12),
            cv2.LINE_AA,
        )
        salient += [(x0, y0), (x0 + sign_w, y0), (x0 + sign_w, y0 + sign_h)]
        section += 1
    return Texture(image, np.array(salient, dtype=float).reshape(-1, 2))


def _person(rng: np.random.Generator, image: Image, box: tuple[int, int, int, int]) -> None:
    """A seated person over a seat: a shirt of any colour and a head of a skin or hair tone."""
    left, top, right, bottom = box
    width = right - left
    shirt = random_colour(rng, 10, 250)
    cv2.rectangle(
        image,
        (left + width // 6, top + (bottom - top) // 3),
        (right - width // 6, bottom),
        shirt,
        -1,
    )
    tone = rng.uniform(0.3, 1.0)
    head: tuple[int, ...] = (int(60 + 90 * tone), int(80 + 110 * tone), int(110 + 130 * tone))
    if rng.random() < 0.4:
        head = random_colour(rng, 10, 90)  # a cap or dark hair
    radius = max(1, width // 4)
    cv2.circle(image, ((left + right) // 2, top + radius), radius, head, -1, cv2.LINE_AA)


def court_floor(
    rng: np.random.Generator, shape: tuple[int, int], texels_per_metre: float
) -> Texture:
    """A wooden court: planks along the length, a painted border, centre line and circle,
    a key at each end. Line crossings and corners are salient."""
    height, width = shape
    wood = np.array([rng.uniform(60, 110), rng.uniform(120, 170), rng.uniform(170, 220)])
    plank = max(2, int(0.12 * texels_per_metre))
    shade = 12.0 * grain(rng, shape, (40.0, 8.0))
    shade += np.repeat(rng.normal(0, 10, (height // plank + 1, 1)), plank, axis=0)[:height]
    image = tinted(wood, shade)
    line = (235, 235, 235)
    thick = max(2, int(0.06 * texels_per_metre))
    margin = int(2.0 * texels_per_metre)
    corners = [(margin, margin), (width - margin, margin), (width - margin, height - margin)]
    corners.append((margin, height - margin))
    cv2.rectangle(image, corners[0], corners[2], line, thick)
    mid = height // 2
    cv2.line(image, (margin, mid), (width - margin, mid), line, thick)
    radius = int(rng.uniform(1.5, 3.0) * texels_per_metre)
    cv2.circle(image, (width // 2, mid), radius, line, thick, cv2.LINE_AA)
    key_w = int(rng.uniform(3.0, 5.0) * texels_per_metre)
    key_h = int(rng.uniform(4.0, 6.0) * texels_per_metre)
    paint = random_colour(rng, 40, 200)
    salient = [*corners, (margin, mid), (width - margin, mid), (width // 2, mid - radius)]
    salient.append((width // 2, mid + radius))
    for top in (margin, height - margin - key_h):
        x0 = width // 2 - key_w // 2
        cv2.rectangle(image, (x0, top), (x0 + key_w, top + key_h), paint, -1)
        cv2.rectangle(image, (x0, top), (x0 + key_w, top + key_h), line, thick)
        salient += [(x0, top), (x0 + key_w, top), (x0, top + key_h), (x0 + key_w, top + key_h)]
    # A logo in the centre circle.
    logo = poster(rng, (radius, radius * 2))
    y0, x0 = mid - radius // 2, width // 2 - radius
    image[y0 : y0 + radius, x0 : x0 + 2 * radius] = logo
    return Texture(image, np.array(salient, dtype=float))


def ceiling(rng: np.random.Generator, shape: tuple[int, int], texels_per_metre: float) -> Texture:
    """A dark roof with a truss grid and round lamps; the lamps are salient."""
    height, width = shape
    image = tinted(np.array([45.0, 45.0, 50.0]), 8.0 * grain(rng, shape, (50.0, 10.0)))
    step = int(rng.uniform(4.0, 8.0) * texels_per_metre)
    for x in range(step // 2, width, step):
        cv2.line(image, (x, 0), (x, height - 1), (110, 110, 115), max(2, step // 30))
    for y in range(step // 2, height, step):
        cv2.line(image, (0, y), (width - 1, y), (110, 110, 115), max(2, step // 30))
    radius = max(3, int(0.4 * texels_per_metre))
    for _ in range(int(width * height / step**2)):
        centre = (int(rng.integers(0, width)), int(rng.integers(0, height)))
        cv2.circle(image, centre, radius, (235, 245, 250), -1, cv2.LINE_AA)
        cv2.circle(image, centre, radius, (90, 90, 90), 2, cv2.LINE_AA)
    # Lamps look all alike: nobody would pick one as a landmark. Signs fixed under the
    # roof would be picked; their corners are salient.
    salient = []
    for _ in range(int(rng.integers(2, 6))):
        w, h = (int(rng.uniform(2.0, 6.0) * texels_per_metre) for _ in range(2))
        x0, y0 = int(rng.integers(0, max(1, width - w))), int(rng.integers(0, max(1, height - h)))
        image[y0 : y0 + h, x0 : x0 + w] = poster(rng, image[y0 : y0 + h, x0 : x0 + w].shape[:2])
        salient += [(x0, y0), (x0 + w, y0), (x0, y0 + h), (x0 + w, y0 + h)]
    return Texture(image, np.array(salient, dtype=float).reshape(-1, 2))


def boards(rng: np.random.Generator, shape: tuple[int, int], texels_per_metre: float) -> Texture:
    """Advertising boards along the edge of the floor: panels of a few metres each, every
    one a small poster; the panels' corners are salient."""
    height, width = shape
    image = np.empty((height, width, 3), np.uint8)
    salient = []
    x = 0
    while x < width:
        w = int(rng.uniform(3.0, 8.0) * texels_per_metre)
        w = min(w, width - x)
        image[:, x : x + w] = poster(rng, (height, w)) if w > 4 else 0
        salient += [(x, 0), (x, height)]
        x += w
    return Texture(image, np.array(salient, dtype=float))


def painted(rng: np.random.Generator, shape: tuple[int, int], texels_per_metre: float) -> Texture:
    """A pillar's or a stage's face: a flat colour with a band and a number; the band's
    corners are salient."""
    height, width = shape
    base = np.array(random_colour(rng, 40, 220), dtype=float)
    image = tinted(base, 8.0 * grain(rng, shape, (20.0, 4.0)))
    band_top = int(rng.uniform(0.2, 0.7) * height)
    band_h = max(4, int(rng.uniform(0.3, 1.0) * texels_per_metre))
    cv2.rectangle(image, (0, band_top), (width - 1, band_top + band_h), random_colour(rng), -1)
    size = min(width, band_h) / 40.0
    cv2.putText(
        image,
        random_word(rng, 2),
        (width // 8, band_top + int(band_h * 0.85)),
        _FONTS[1],
        size,
        random_colour(rng),
        max(1, int(size * 2)),
        cv2.LINE_AA,
    )
    salient = [(0, band_top), (width, band_top), (0, band_top + band_h), (width, band_top + band_h)]
    return Texture(image, np.array(salient, dtype=float))


def screen(rng: np.random.Generator, shape: tuple[int, int], texels_per_metre: float) -> Texture:
    """A scoreboard face: black with bright digits and a coloured frame; its corners and
    the digits' boxes are salient."""
    height, width = shape
    image = np.zeros((height, width, 3), np.uint8)
    image[:] = (25, 25, 25)
    frame = random_colour(rng, 80, 255)
    thick = max(2, int(0.1 * texels_per_metre))
    cv2.rectangle(image, (0, 0), (width - 1, height - 1), frame, thick)
    salient = [(0, 0), (width, 0), (0, height), (width, height)]
    scale = height / 60.0
    for slot in range(2):
        text = f"{int(rng.integers(0, 130)):03d}"
        x = int((0.1 + 0.5 * slot) * width)
        y = int(0.75 * height)
        colour = random_colour(rng, 120, 255)
        cv2.putText(image, text, (x, y), _FONTS[0], scale, colour, max(2, int(scale * 3)))
        (w, h), _ = cv2.getTextSize(text, _FONTS[0], scale, max(2, int(scale * 3)))
        salient += [(x, y - h), (x + w, y)]
    return Texture(image, np.array(salient, dtype=float))
