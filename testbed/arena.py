"""An arena around two phones: a hall with things that look alike from the other side.

The hall is the suite's (:mod:`testbed.hall`: a court floor, whose lines are the same turned
180 degrees, stands, walls with posters, advertising boards, roof, pillars, equipment, a
stage, a scoreboard). Added to it (:mod:`testbed.prints`):

- **banners** hung across the hall, above the line between the phones: one phone sees
  their front, the other their back; mesh banners (the print shows through, mirrored) and
  banners printed to read from both sides; a sponsor has several alike;
- **signs** alike: on the side walls at one height, and hanging across the hall, printed
  on both sides;
- **posters** repeated along the side walls, at one height;
- **mats** on the floor, all alike, each print the same turned 180 degrees;
- **pillars**, all alike, along the floor's sides;
- a **video board** on a side wall that shows something else in each photo;
- **spotlights** whose pools of light move between the two photos.

Everything is drawn from the caller's random generator: the same seed gives the same arena.
Elements that would stand between the phones are left out (each phone sees the other).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from . import prints, textures
from .hall import (
    COARSE,
    FINE,
    Layout,
    Paint,
    box_faces,
    clear_of_sight,
    furniture,
    hall_paints,
    layout,
    shell,
)
from .render import Light, Surface
from .scenes import Camera
from .textures import Texture

_ABOVE_FLOOR = 0.02  # m: a mat's thickness
_CLEARANCE = 2.0  # m: a hanging banner's lower edge stays this far above the higher phone


@dataclass(frozen=True)
class Arena:
    """What each photo shows: the surfaces (the same but for the video board's picture)
    and the spotlights' pools at the moment it was taken."""

    surfaces1: list[Surface]
    surfaces2: list[Surface]
    lights1: list[Light]
    lights2: list[Light]


@dataclass(frozen=True)
class _Sight:
    """Where both phones look: the hall, the height a hanging print keeps above the
    higher phone (``lowest``, y down), and how far to either side of the line between the
    phones both photos reach."""

    hall: Layout
    lowest: float
    length: float
    tangents: tuple[float, float]  # of each phone's half field across its shorter side

    @classmethod
    def of(cls, hall: Layout, camera1: Camera, camera2: Camera) -> _Sight:
        tangents = tuple(
            min(camera.intrinsics[0, 2], camera.intrinsics[1, 2]) / camera.intrinsics[0, 0]
            for camera in (camera1, camera2)
        )
        return cls(
            hall,
            min(camera1.centre[1], camera2.centre[1]) - _CLEARANCE,
            float(camera2.centre[2] - camera1.centre[2]),
            (float(tangents[0]), float(tangents[1])),
        )

    def reach(self, along: float) -> float:
        """Metres to either side that both photos show ``along`` (0-1) of the way."""
        first, second = self.tangents
        return min(along * self.length * first, (1.0 - along) * self.length * second)

    def spot(self, rng: np.random.Generator, width: float = 0.0) -> tuple[float, float]:
        """(x, z) m of something ``width`` m wide (along x) that both photos show, on the
        floor: 25-75 % of the way from phone 1 to phone 2."""
        along = rng.uniform(0.25, 0.75)
        reach = min(self.reach(along), self.hall.half_width - 0.5)
        return rng.uniform(-reach, reach) - width / 2, along * self.length


def build_arena(rng: np.random.Generator, camera1: Camera, camera2: Camera) -> Arena:
    """The arena around the two phones (module docstring)."""
    hall = layout(rng, camera1.centre, camera2.centre)
    surfaces = shell(hall, hall_paints(rng))
    sight = _Sight.of(hall, camera1, camera2)
    elements = [
        *furniture(rng, hall),
        *_pillars(rng, sight),
        *_banners(rng, sight),
        *_hanging_signs(rng, sight),
        *_side_prints(rng, sight),
        *_mats(rng, sight),
    ]
    surfaces += clear_of_sight(elements, camera1, camera2)
    board1, board2 = _video_board(rng, sight)
    return Arena(
        [*surfaces, board1],
        [*surfaces, board2],
        _spotlights(rng, sight),
        _spotlights(rng, sight),
    )


def _same(make: Callable[[tuple[int, int], float], Texture]) -> Paint:
    """A paint that gives every surface of one size the same texture (things alike)."""
    made: dict[tuple[int, int], Texture] = {}

    def paint(shape: tuple[int, int], density: float) -> Texture:
        if shape not in made:
            made[shape] = make(shape, density)
        return made[shape]

    return paint, FINE


def _pillars(rng: np.random.Generator, sight: _Sight) -> list[list[Surface]]:
    """One to four pillars on the floor, all of one size and paint."""
    hall = sight.hall
    paint = _same(lambda shape, density: textures.painted(rng, shape, density))
    size = rng.uniform(0.6, 1.2)
    boxes = []
    for _ in range(int(rng.integers(1, 5))):
        x, z = sight.spot(rng)
        low = np.array([x - size / 2, hall.roof_y, z - size / 2])
        high = np.array([x + size / 2, hall.floor_y, z + size / 2])
        boxes.append(box_faces("pillar", low, high, paint))
    return boxes


def _across(
    rng: np.random.Generator,
    sight: _Sight,
    *,
    size: tuple[float, float],
    texture: Texture,
    back: textures.Image,
    kind: str,
) -> list[Surface]:
    """A print ``size`` (width, height) m hung across the hall, facing phone 1 with
    ``texture`` and phone 2 with ``back``; none when the roof is too low for it."""
    width, height = size
    top = sight.lowest - height - rng.uniform(0.0, 4.0)
    if top < sight.hall.roof_y + 0.5:
        return []
    x, z = sight.spot(rng, width)
    # across +x, down +y: the front's normal is -z, towards phone 1.
    return [
        Surface(
            np.array([x, top, z]),
            np.array([width, 0.0, 0.0]),
            np.array([0.0, height, 0.0]),
            texture,
            kind,
            back,
        )
    ]


def _banners(rng: np.random.Generator, sight: _Sight) -> list[list[Surface]]:
    """Two to seven banners across the hall, from one to three sponsors' designs; each
    design is a mesh (seen mirrored from behind, every salient texel the same point from
    both sides) or printed on both sides (only the banner's corners are the same points)."""
    designs = []
    for _ in range(int(rng.integers(1, 4))):
        size = (rng.uniform(3.0, 9.0), rng.uniform(1.2, 3.5))
        shape = (round(size[1] * FINE), round(size[0] * FINE))
        printed = prints.banner(rng, shape, FINE)
        if rng.random() < 0.5:  # a mesh: the back is the front, seen from behind
            designs.append((size, printed, printed.image))
        else:
            corners_only = textures.Texture(printed.image, printed.salient[:4])
            designs.append((size, corners_only, prints.mirrored(printed.image)))
    banners = []
    for index in range(int(rng.integers(2, 8))):
        size, texture, back = designs[index % len(designs)]
        banners.append(_across(rng, sight, size=size, texture=texture, back=back, kind="banner"))
    return [banner for banner in banners if banner]


def _hanging_signs(rng: np.random.Generator, sight: _Sight) -> list[list[Surface]]:
    """Up to five signs alike hung across the hall, printed to read from both sides."""
    size = (rng.uniform(1.0, 2.0), rng.uniform(0.4, 0.8))
    texture = prints.sign(rng, (round(size[1] * FINE), round(size[0] * FINE)))
    back = prints.mirrored(texture.image)
    signs = [
        _across(rng, sight, size=size, texture=texture, back=back, kind="sign")
        for _ in range(int(rng.integers(0, 6)))
    ]
    return [sign for sign in signs if sign]


def _along_side(
    x: float,
    side: float,
    *,
    z: float,
    y: float,
    size: tuple[float, float],
    texture: Texture,
    kind: str,
) -> Surface:
    """A print of ``size`` (width, height) m facing the middle of the hall from ``side``
    (-1 or 1) at ``x``, its top left at height ``y`` and at ``z`` (seen from the middle,
    across runs right)."""
    width, height = size
    # From the middle, the left side (x < 0) reads towards +z, the right one towards -z.
    across = np.array([0.0, 0.0, width if side < 0 else -width])
    return Surface(
        np.array([x, y, z]),
        across,
        np.array([0.0, height, 0.0]),
        texture,
        kind,
    )


def _side_prints(rng: np.random.Generator, sight: _Sight) -> list[list[Surface]]:
    """Rows of signs alike and of posters alike hung along the hall to either side of the
    phones, each row at one height, above them (a wall of screens, a gantry)."""
    hall = sight.hall
    rows: list[list[Surface]] = []
    for kind in ("sign", "poster", "poster"):
        if kind == "sign":
            size = (rng.uniform(1.0, 2.0), rng.uniform(0.4, 0.8))
            texture = prints.sign(rng, (round(size[1] * FINE), round(size[0] * FINE)))
        else:
            size = (rng.uniform(1.5, 4.0), rng.uniform(1.0, 3.0))
            shape = (round(size[1] * COARSE), round(size[0] * COARSE))
            texture = textures.Texture(
                textures.poster(rng, shape),
                np.array(prints.corners(0, 0, shape[1], shape[0]), dtype=float),
            )
        y = sight.lowest - size[1] - rng.uniform(0.0, 5.0)
        if y < hall.roof_y + 0.5:
            continue
        side = rng.choice([-1.0, 1.0])
        x = side * rng.uniform(0.6, 1.0) * sight.reach(0.5)
        pitch = size[0] + rng.uniform(2.0, 10.0)
        z = hall.floor_start + rng.uniform(0.0, pitch)
        while z + size[0] < hall.floor_end:
            start = z if side < 0 else z + size[0]
            rows.append([_along_side(x, side, z=start, y=y, size=size, texture=texture, kind=kind)])
            z += pitch
    return rows


def _mats(rng: np.random.Generator, sight: _Sight) -> list[list[Surface]]:
    """Two to six mats alike on the floor, lengthwise or crosswise."""
    size = (rng.uniform(2.0, 4.0), rng.uniform(1.0, 2.0))
    texture = prints.mat(rng, (round(size[1] * FINE), round(size[0] * FINE)), FINE)
    # Turned a quarter (counter-clockwise): texel (x, y) goes to (y, W - x).
    width_texels = texture.image.shape[1]
    turned = textures.Texture(
        np.ascontiguousarray(np.rot90(texture.image)),
        np.column_stack([texture.salient[:, 1], width_texels - texture.salient[:, 0]]),
    )
    mats = []
    y = sight.hall.floor_y - _ABOVE_FLOOR
    for _ in range(int(rng.integers(2, 7))):
        lengthwise = rng.random() < 0.5
        # across runs along x and down along -z (seen from above); a mat turned 90 degrees
        # swaps its sides.
        width, depth = (size[1], size[0]) if lengthwise else size
        chosen = turned if lengthwise else texture
        x, z = sight.spot(rng, width)
        mats.append(
            [
                Surface(
                    np.array([x, y, z]),
                    np.array([width, 0.0, 0.0]),
                    np.array([0.0, 0.0, -depth]),
                    chosen,
                    "mat",
                )
            ]
        )
    return mats


def _video_board(rng: np.random.Generator, sight: _Sight) -> tuple[Surface, Surface]:
    """A video board hung to one side, facing the middle: the same frame, another picture
    in each photo."""
    size = (rng.uniform(4.0, 8.0), rng.uniform(2.0, 4.0))
    shape = (round(size[1] * COARSE), round(size[0] * COARSE))
    frame = textures.random_colour(rng, 0, 255)
    thick = max(2, int(0.1 * COARSE))
    side = rng.choice([-1.0, 1.0])
    top = max(sight.hall.roof_y + 0.5, sight.lowest - size[1] - rng.uniform(0.0, 3.0))
    along = rng.uniform(0.35, 0.65)
    x = side * rng.uniform(0.7, 1.0) * sight.reach(along)
    start = along * sight.length - (size[0] / 2 if side < 0 else -size[0] / 2)

    def board() -> Surface:
        texture = prints.video_board(rng, shape, frame, thick)
        return _along_side(x, side, z=start, y=top, size=size, texture=texture, kind="screen")

    return board(), board()


def _spotlights(rng: np.random.Generator, sight: _Sight) -> list[Light]:
    """Three to six pools of light where both phones look, on the floor or higher up (on
    the hanging prints)."""
    lights = []
    for _ in range(int(rng.integers(3, 7))):
        x, z = sight.spot(rng)
        y = rng.uniform(sight.lowest - 4.0, sight.hall.floor_y)
        lights.append(Light(np.array([x, y, z]), rng.uniform(2.0, 6.0), rng.uniform(0.3, 1.2)))
    return lights
