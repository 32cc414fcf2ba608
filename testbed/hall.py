"""A hall around two phones: floor, stands, walls, boards, pillars, a stage, a scoreboard.

The phones come from :func:`testbed.phones.phone_scene` (phone 1 at the origin, phone 2
20-80 m away along +z, heights a few metres apart; y points down). Each sits in the stand
at its end of the hall and photographs the other end. What both photos share is what lies
along the sides and between them: the floor and its lines, the side stands with their
rows of people and section signs, the advertising boards around the floor, posters on the
side walls, pillars, a stage on one side, the scoreboard hanging over the middle, the
roof. Each end stand is seen by one phone only.

Every element is a :class:`~testbed.render.Surface` (a textured rectangle, drawn on one
side); boxes are their faces. Sizes are drawn from the random generator: the same seed
gives the same hall.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from shared_solver.projective import Array

from . import textures
from .render import Surface
from .scenes import Camera
from .textures import Texture

# Texels per metre: enough that a 26 mm lens at 2560 px sees about one texel per pixel
# 20-40 m away; nearer, texture is enlarged (soft), farther, averaged (mip levels).
FINE = 60.0
COARSE = 40.0
ROOF = 20.0
_SEATED_EYES = 1.2  # m from a step of the stand to a seated person's eyes


Maker = Callable[[tuple[int, int], float], Texture]
Paint = tuple[Maker, float]  # how to make a texture, and at how many texels per metre


def rect(kind: str, origin: Array, across: Array, down: Array, paint: Paint) -> Surface:
    """A surface whose texture is made by ``paint`` (maker, texels per metre)."""
    make, density = paint
    shape = (
        max(8, round(float(np.linalg.norm(down)) * density)),
        max(8, round(float(np.linalg.norm(across)) * density)),
    )
    return Surface(origin, across, down, make(shape, density), kind)


def box_faces(
    kind: str, low: Array, high: Array, paint: Paint, *, top: bool = False, bottom: bool = False
) -> list[Surface]:
    """The four vertical faces of an axis-aligned box from ``low`` to ``high`` (3,) m (y
    down), plus its top or bottom, each with its own texture, drawn outwards."""
    (x0, y0, z0), (x1, y1, z1) = low, high
    height = np.array([0.0, y1 - y0, 0.0])
    faces = [
        # -z face (seen from smaller z), +x, +z, -x: going round, each read upright.
        rect(kind, np.array([x0, y0, z0]), np.array([x1 - x0, 0.0, 0.0]), height, paint),
        rect(kind, np.array([x1, y0, z0]), np.array([0.0, 0.0, z1 - z0]), height, paint),
        rect(kind, np.array([x1, y0, z1]), np.array([x0 - x1, 0.0, 0.0]), height, paint),
        rect(kind, np.array([x0, y0, z1]), np.array([0.0, 0.0, z0 - z1]), height, paint),
    ]
    flat_x = np.array([x1 - x0, 0.0, 0.0])
    if top:  # seen from above (smaller y)
        faces.append(
            rect(kind, np.array([x0, y0, z1]), flat_x, np.array([0.0, 0.0, z0 - z1]), paint)
        )
    if bottom:  # seen from below
        faces.append(
            rect(kind, np.array([x0, y1, z0]), flat_x, np.array([0.0, 0.0, z1 - z0]), paint)
        )
    return faces


@dataclass(frozen=True)
class Layout:
    """The hall's dimensions (m; y down, phone 1 at z = 0, phone 2 at z = length)."""

    floor_y: float
    floor_start: float  # z where the floor begins in front of phone 1
    floor_end: float  # ... and ends in front of phone 2
    half_width: float  # of the floor
    side_rise: float  # height of the side stands
    side_run: float  # their depth
    roof_y: float
    back1: float  # z of the end wall behind phone 1
    back2: float  # ... behind phone 2
    end_top1: float  # y of the top row of the end stand behind phone 1
    end_top2: float

    @property
    def outer(self) -> float:
        """Half the distance between the side walls."""
        return self.half_width + self.side_run


def build_hall(rng: np.random.Generator, camera1: Camera, camera2: Camera) -> list[Surface]:
    """Every surface of a hall around the two phones (module docstring).

    Elements that would stand between the phones (a pillar, the scoreboard, the stage) are
    left out: each phone must see the other.
    """
    hall = layout(rng, camera1.centre, camera2.centre)
    surfaces = shell(hall, hall_paints(rng))
    return surfaces + clear_of_sight(furniture(rng, hall), camera1, camera2)


def clear_of_sight(
    elements: list[list[Surface]], camera1: Camera, camera2: Camera
) -> list[Surface]:
    """The faces of the elements (each a list of faces) that do not stand between the
    phones: each phone must see the other."""
    return [
        face
        for element in elements
        if not any(blocks(face, camera1.centre, camera2.centre) for face in element)
        for face in element
    ]


def layout(rng: np.random.Generator, c1: Array, c2: Array) -> Layout:
    length = float(c2[2] - c1[2])
    floor_y = max(c1[1], c2[1]) + rng.uniform(3.0, 9.0)  # y is down: the floor is below both
    heights = (floor_y - c1[1], floor_y - c2[1])
    # Each end stand rises behind its phone, steep enough to leave the middle 40 % as floor.
    slopes = [
        max(math.radians(rng.uniform(25.0, 35.0)), math.atan((h - _SEATED_EYES) / (0.3 * length)))
        for h in heights
    ]
    floor_start = c1[2] + (heights[0] - _SEATED_EYES) / math.tan(slopes[0])
    floor_end = c2[2] - (heights[1] - _SEATED_EYES) / math.tan(slopes[1])
    half_width = max(8.0, length * rng.uniform(0.2, 0.35))
    side_slope = math.radians(rng.uniform(25.0, 35.0))
    side_rise = rng.uniform(8.0, 18.0)
    roof_y = min(c1[1], c2[1], floor_y - side_rise) - rng.uniform(8.0, 20.0)
    back1, back2 = c1[2] - rng.uniform(6.0, 12.0), c2[2] + rng.uniform(6.0, 12.0)
    return Layout(
        floor_y=floor_y,
        floor_start=floor_start,
        floor_end=floor_end,
        half_width=half_width,
        side_rise=side_rise,
        side_run=side_rise / math.tan(side_slope),
        roof_y=roof_y,
        back1=back1,
        back2=back2,
        end_top1=floor_y - (floor_start - back1) * math.tan(slopes[0]),
        end_top2=floor_y - (back2 - floor_end) * math.tan(slopes[1]),
    )


@dataclass(frozen=True)
class Paints:
    """How each part of a hall's shell is painted."""

    floor: Paint
    roof: Paint
    stand: Paint
    wall: Paint
    boards: Paint


def hall_paints(rng: np.random.Generator) -> Paints:
    """The hall's: a wooden court, a dark roof with lamps, seated stands, walls with
    posters, advertising boards (each a different poster)."""
    return Paints(
        floor=(lambda shape, density: textures.court_floor(rng, shape, density), COARSE),
        roof=(lambda shape, density: textures.ceiling(rng, shape, density), ROOF),
        stand=(lambda shape, density: textures.seating(rng, shape, density), COARSE),
        wall=(lambda shape, density: textures.wall_with_posters(rng, shape, density), COARSE),
        boards=(lambda shape, density: textures.boards(rng, shape, density), FINE),
    )


def shell(hall: Layout, paints: Paints) -> list[Surface]:
    """The floor, the roof, the stands, walls and boards of both sides and both ends."""
    seats, posters, boards = paints.stand, paints.wall, paints.boards
    outer = hall.outer
    surfaces = [
        rect(  # the floor, read from phone 1's end
            "floor",
            np.array([-hall.half_width, hall.floor_y, hall.floor_end]),
            np.array([2 * hall.half_width, 0.0, 0.0]),
            np.array([0.0, 0.0, hall.floor_start - hall.floor_end]),
            paints.floor,
        ),
        rect(  # the roof, seen from below
            "roof",
            np.array([-outer, hall.roof_y, hall.back1]),
            np.array([2 * outer, 0.0, 0.0]),
            np.array([0.0, 0.0, hall.back2 - hall.back1]),
            paints.roof,
        ),
    ]
    stand_top = hall.floor_y - hall.side_rise
    for side in (-1.0, 1.0):
        # Looking at a side from the middle, "across" runs to the right: from phone 1's end
        # to phone 2's on the left side (x < 0), the other way on the right.
        start, stop = (hall.back1, hall.back2) if side < 0 else (hall.back2, hall.back1)
        along = np.array([0.0, 0.0, stop - start])
        surfaces += [
            rect(  # the side stand, from its back row (top) to the floor's edge
                "stand",
                np.array([side * outer, stand_top, start]),
                along,
                np.array([-side * hall.side_run, hall.side_rise, 0.0]),
                seats,
            ),
            rect(  # the side wall above the stand
                "wall",
                np.array([side * outer, hall.roof_y, start]),
                along,
                np.array([0.0, stand_top - hall.roof_y, 0.0]),
                posters,
            ),
            rect(  # advertising boards around the floor, 1 m high
                "boards",
                np.array([side * hall.half_width, hall.floor_y - 1.0, start]),
                along,
                np.array([0.0, 1.0, 0.0]),
                boards,
            ),
        ]
    ends = (
        (1.0, hall.back1, hall.end_top1, hall.floor_start),
        (-1.0, hall.back2, hall.end_top2, hall.floor_end),
    )
    for sign, back, top, edge in ends:
        # Seen from the other end: "across" runs to that phone's right.
        across = np.array([-2 * sign * outer, 0.0, 0.0])
        surfaces += [
            rect(  # the end stand behind the phone
                "stand",
                np.array([sign * outer, top, back]),
                across,
                np.array([0.0, hall.floor_y - top, edge - back]),
                seats,
            ),
            rect(  # the end wall above it
                "wall",
                np.array([sign * outer, hall.roof_y, back]),
                across,
                np.array([0.0, top - hall.roof_y, 0.0]),
                posters,
            ),
        ]
    return surfaces


def furniture(rng: np.random.Generator, hall: Layout) -> list[list[Surface]]:
    """Boxes in the hall, each a list of faces: pillars, equipment, a stage, a scoreboard."""
    paint: Paint = (lambda shape, density: textures.painted(rng, shape, density), FINE)
    screen: Paint = (lambda shape, density: textures.screen(rng, shape, density), FINE / 2)
    boxes: list[list[Surface]] = []
    for _ in range(int(rng.integers(0, 5))):  # pillars along the sides of the floor
        side = rng.choice([-1.0, 1.0])
        size = rng.uniform(0.6, 1.2)
        x = side * (hall.half_width - rng.uniform(0.5, 3.0))
        z = rng.uniform(hall.floor_start, hall.floor_end)
        low = np.array([x - size / 2, hall.roof_y, z - size / 2])
        high = np.array([x + size / 2, hall.floor_y, z + size / 2])
        boxes.append(box_faces("pillar", low, high, paint))
    for _ in range(int(rng.integers(1, 5))):  # equipment on the floor: cases, desks, speakers
        footprint = rng.uniform(0.8, 3.0, 2)
        tall = rng.uniform(0.6, 2.5)
        x = rng.uniform(-hall.half_width + footprint[0], hall.half_width - footprint[0])
        z = rng.uniform(hall.floor_start + footprint[1], hall.floor_end - footprint[1])
        low = np.array([x - footprint[0] / 2, hall.floor_y - tall, z - footprint[1] / 2])
        high = np.array([x + footprint[0] / 2, hall.floor_y, z + footprint[1] / 2])
        boxes.append(box_faces("equipment", low, high, paint, top=True))
    length = hall.floor_end - hall.floor_start
    if rng.random() < 0.6:  # a stage on one side of the floor
        side = rng.choice([-1.0, 1.0])
        depth, span = rng.uniform(4.0, 8.0), rng.uniform(0.2, 0.5) * length
        z = rng.uniform(hall.floor_start, hall.floor_end - span)
        inner, edge = side * (hall.half_width - depth), side * hall.half_width
        low = np.array([min(inner, edge), hall.floor_y - rng.uniform(1.0, 1.8), z])
        high = np.array([max(inner, edge), hall.floor_y, z + span])
        boxes.append(box_faces("stage", low, high, paint, top=True))
    if rng.random() < 0.7:  # a scoreboard hung over the middle
        width, tall, deep = rng.uniform(5.0, 9.0), rng.uniform(3.0, 5.0), rng.uniform(5.0, 9.0)
        top = hall.roof_y + rng.uniform(2.0, 6.0)
        middle = 0.5 * (hall.floor_start + hall.floor_end)
        low = np.array([-width / 2, top, middle - deep / 2])
        high = np.array([width / 2, top + tall, middle + deep / 2])
        boxes.append(box_faces("scoreboard", low, high, screen, bottom=True))
    return boxes


def blocks(surface: Surface, start: Array, end: Array) -> bool:
    """Whether the segment from ``start`` to ``end`` (3,) crosses the surface's rectangle."""
    normal = surface.normal
    a, b = normal @ (start - surface.origin), normal @ (end - surface.origin)
    if a * b > 0 or a == b:
        return False
    point = start + (end - start) * (a / (a - b)) - surface.origin
    s = point @ surface.across / (surface.across @ surface.across)
    t = point @ surface.down / (surface.down @ surface.down)
    return bool(0.0 <= s <= 1.0 and 0.0 <= t <= 1.0)
