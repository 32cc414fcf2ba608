"""The answer drawn on the photos: what each phone shows, checked pixel by pixel."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any, Literal

import cv2
import numpy as np
import pytest
from numpy.typing import ArrayLike

from shared_solver import ErrorCode, SolverError, SolveResult, solve
from shared_solver.drawing.overlay import draw_overlay
from shared_solver.drawing.palette import (
    FRIEND_COLOUR_BGR,
    LANDMARK_COLOURS_BGR,
    LANDMARK_COLOURS_HEX,
    SUSPECT_COLOUR_BGR,
    landmark_colour,
    landmark_colour_hex,
)
from shared_solver.result import Ellipse, Uncertainty
from testbed.scenes import Scene, facing_scene, solved, temple_scene

TEMPLE = Path(__file__).parents[1] / "data" / "temple"
GREY = 128


# --- helpers ----------------------------------------------------------------------------


def scene(seed: int, landmarks: int = 8, **kwargs: Any) -> Scene:
    return facing_scene(np.random.default_rng(seed), landmarks, **kwargs)


def answer(
    s: Scene,
    count: int,
    *,
    photo2_shift: ArrayLike = (0.0, 0.0),
    taps2: np.ndarray | None = None,
    **kwargs: Any,
) -> SolveResult:
    """solve() with the friend tapped in photo 1 (unless ``epipole1`` says otherwise) and the
    first ``count`` landmarks (photo 2's at ``taps2`` if given)."""
    return solve(
        s.landmarks1[:count],
        (s.landmarks2 if taps2 is None else taps2)[:count] + np.asarray(photo2_shift),
        **{"epipole1": s.epipole1, **s.sizes} | kwargs,
    )


def grey(size: tuple[int, int], level: int = GREY) -> np.ndarray:
    width, height = size
    return np.full((height, width, 3), level, np.uint8)


def changed(before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """(H, W) mask of the pixels the overlay painted."""
    return np.any(before != after, axis=2)


def painted(image: np.ndarray, colour: tuple[int, int, int]) -> np.ndarray:
    """(H, W) mask of pixels of exactly ``colour`` (the inside of a stroke, not its edge)."""
    return np.all(image == np.array(colour, np.uint8), axis=2)


def pixels(mask: np.ndarray) -> np.ndarray:
    """(M, 2) x, y of the set pixels."""
    rows, cols = np.nonzero(mask)
    return np.column_stack([cols, rows]).astype(float)


def near(mask: np.ndarray, point: ArrayLike, radius: float) -> bool:
    found = pixels(mask)
    return bool(len(found)) and float(np.min(np.hypot(*(found - point).T))) <= radius


def at(image: np.ndarray, point: Iterable[float]) -> tuple[int, int, int]:
    x, y = (round(float(v)) for v in point)
    b, g, r = image[y, x]
    return int(b), int(g), int(r)


def diagonal(image: np.ndarray) -> float:
    return math.hypot(image.shape[0], image.shape[1])


def distance_to_conic(conic: np.ndarray, points: np.ndarray) -> np.ndarray:
    """First-order (Sampson) distance in px of each (x, y) point from x^T C x = 0."""
    h = np.column_stack([points, np.ones(len(points))])
    value = np.einsum("ni,ij,nj->n", h, conic, h)
    gradient = 2.0 * np.hypot(*(h @ conic)[:, :2].T)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(value == 0, 0.0, np.abs(value) / gradient)


def zero_crossings(conic: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """(H, W) mask of pixels where x^T C x changes sign towards the next pixel right or down:
    the curve rasterised independently of the overlay's own sampling."""
    rows, cols = np.indices(shape[:2], dtype=float)
    h = np.stack([cols, rows, np.ones(shape[:2])], axis=-1)
    positive = np.einsum("...i,ij,...j->...", h, conic, h) > 0
    mask = np.zeros(shape[:2], bool)
    mask[:, :-1] |= positive[:, :-1] != positive[:, 1:]
    mask[:-1, :] |= positive[:-1, :] != positive[1:, :]
    return mask


def gap_to(paint: np.ndarray, wanted: np.ndarray) -> float:
    """The largest distance (px) from a ``wanted`` pixel to the nearest painted one."""
    to_paint = cv2.distanceTransform((~paint).astype(np.uint8), cv2.DIST_L2, 0)
    return float(to_paint[wanted].max())


def distance_to_line(
    points: np.ndarray, through: ArrayLike, direction: Sequence[float] | np.ndarray
) -> np.ndarray:
    direction = np.asarray(direction, float) / np.hypot(*direction)
    offset = points - np.asarray(through)
    return np.abs(offset[:, 0] * direction[1] - offset[:, 1] * direction[0])


# --- the image itself -------------------------------------------------------------------


@pytest.mark.parametrize("number", [2, 1])
def test_a_new_photo_of_the_same_size_is_returned_and_the_input_is_untouched(
    number: Literal[1, 2],
) -> None:
    s = scene(2)
    result = answer(s, 5)
    photo = grey(s.image_size2)
    original = photo.copy()
    points = s.landmarks2[:5] if number == 2 else s.landmarks1[:5]
    drawn = draw_overlay(photo, result, photo=number, points=points)
    assert drawn.shape == photo.shape
    assert drawn.dtype == np.uint8
    assert np.array_equal(photo, original)
    assert changed(photo, drawn).any()


def test_a_grey_photo_comes_back_in_colour() -> None:
    s = scene(2)
    photo = grey(s.image_size2)[:, :, 0]
    drawn = draw_overlay(photo, answer(s, 5))
    assert drawn.shape == (*photo.shape, 3)
    assert painted(drawn, FRIEND_COLOUR_BGR).any()


# --- photo 2: where the friend was found -------------------------------------------------


def test_the_friend_is_framed_and_stays_visible() -> None:
    """A precise answer (its region smaller than a person): brackets around the friend, a
    label beside, and nothing painted on a person-sized spot around the answer."""
    s = scene(2)
    result = answer(s, 5)
    assert result.uncertainty is not None
    assert result.uncertainty.ellipse is not None
    assert max(result.uncertainty.ellipse.axes) < 10  # precise
    photo = grey(s.image_size2)
    drawn = draw_overlay(photo, result)
    e2 = np.array(result.epipole2)
    size = diagonal(photo)
    paint = changed(photo, drawn)
    distances = np.hypot(*(pixels(paint) - e2).T)
    person = size / 70  # a person 40 m away on a phone's main camera is size / 90
    assert distances.min() > person  # the friend shows through
    frame = painted(drawn, FRIEND_COLOUR_BGR)
    # Brackets all round: friend-coloured strokes in each quadrant, near the frame.
    offsets = (
        pixels(frame & (np.hypot(*(np.indices(paint.shape)[::-1] - e2[:, None, None])) < size / 25))
        - e2
    )
    for sx, sy in ((-1, -1), (1, -1), (-1, 1), (1, 1)):
        assert np.any((np.sign(offsets[:, 0]) == sx) & (np.sign(offsets[:, 1]) == sy))
    # And nothing far away: the frame, its leader and its label stay near the friend.
    assert distances.max() < size / 8


def test_without_a_region_the_friend_is_framed_as_likely() -> None:
    s = scene(2)
    sure = answer(s, 5)
    unsure = sure.model_copy(update={"uncertainty": Uncertainty(ellipse=None)})
    photo = grey(s.image_size2)
    drawn, plain = draw_overlay(photo, unsure), draw_overlay(photo, sure)
    e2 = np.array(sure.epipole2)
    assert np.hypot(*(pixels(changed(photo, drawn)) - e2).T).min() > diagonal(photo) / 70
    assert not np.array_equal(drawn, plain)  # "friend?", not "friend"


@pytest.mark.parametrize("count", [5, 4], ids=["frame", "curve"])
def test_marks_have_a_dark_outline_that_reads_on_a_white_photo(count: int) -> None:
    s = scene(2)
    photo = grey(s.image_size2, level=255)
    drawn = draw_overlay(photo, answer(s, count), points=s.landmarks2[:count])
    paint = changed(photo, drawn)
    dark = paint & (drawn.max(axis=2) < 60)
    size = diagonal(photo)
    for landmark in s.landmarks2[:count]:
        assert near(dark, landmark, size / 100)
    if count == 5:
        assert near(dark, s.epipole2, size / 20)
    else:  # the curve: dark edges all along it, away from the landmarks too
        rows, cols = np.indices(paint.shape)
        away = np.ones_like(paint)
        for x, y in s.landmarks2[:count]:
            away &= np.hypot(cols - x, rows - y) > size / 20
        assert (dark & away).sum() > 0.2 * (paint & away).sum()


def test_the_uncertainty_ellipse_is_drawn_where_opencv_draws_it() -> None:
    s = scene(0)  # a long ellipse (about 200 x 22 px), larger than a person
    result = answer(s, 5)
    assert result.uncertainty is not None
    ellipse = result.uncertainty.ellipse
    assert ellipse is not None
    photo = grey(s.image_size2)
    drawn = draw_overlay(photo, result)
    # Oracle: OpenCV's own ellipse (fine at these moderate sizes), 1 px wide, to 1/16 px
    # (4 fractional bits).
    oracle = np.zeros(photo.shape[:2], np.uint8)
    centre, axes = (tuple(round(16 * v) for v in pair) for pair in (ellipse.center, ellipse.axes))
    cv2.ellipse(oracle, centre, axes, ellipse.angle_deg, 0, 360, 255, 1, cv2.LINE_8, 4)
    # Inside the brackets' box (they are on its edges, the label outside it) only the
    # ellipse is drawn. Clearly painted: not the faint anti-aliased fringe around strokes.
    a, b = ellipse.axes
    theta = math.radians(ellipse.angle_deg)
    reach = (
        math.hypot(a * math.cos(theta), b * math.sin(theta)),
        math.hypot(a * math.sin(theta), b * math.cos(theta)),
    )
    rows, cols = np.indices(oracle.shape)
    inside = (np.abs(cols - ellipse.center[0]) < reach[0] + 4) & (
        np.abs(rows - ellipse.center[1]) < reach[1] + 4
    )
    paint = (np.abs(drawn.astype(int) - photo).max(axis=2) > 16) & inside
    assert paint.sum() > 200
    assert gap_to(oracle > 0, paint) < 6  # every stroke pixel hugs the true ellipse
    assert gap_to(paint, oracle > 0) < 2  # and all of it is drawn


def test_an_arrow_at_the_right_border_points_to_friend1_beyond_it() -> None:
    s = scene(1)
    width, height = s.image_size2
    # Sliding photo 2's landmarks sideways slides the answer with them, off the photo.
    centred = answer(s, 5)
    assert centred.epipole2 is not None
    result = answer(s, 5, photo2_shift=(width + 400 - centred.epipole2[0], 0.0))
    assert result.epipole2 is not None
    x, y = result.epipole2
    assert x > width + 300
    photo = grey(s.image_size2)
    drawn = draw_overlay(photo, result)
    paint = pixels(changed(photo, drawn))
    assert paint[:, 0].min() > width / 2  # no frame, nothing on the far side
    # The arrow lies on the ray from the photo's centre to friend 1, up to the border.
    arrow = pixels(painted(drawn, FRIEND_COLOUR_BGR))
    centre = np.array([width / 2, height / 2])
    on_ray = arrow[distance_to_line(arrow, centre, (x - centre[0], y - centre[1])) < 2]
    assert on_ray[:, 0].max() > width - diagonal(photo) / 15
    assert on_ray[:, 0].min() < width - diagonal(photo) / 10  # a shaft, not a dot


def at_infinity(s: Scene, direction: tuple[float, float]) -> SolveResult:
    """The answer of 5 landmarks, moved to friend 1 at infinity along ``direction`` (photo 2's
    px), with no region: an answer the scenes do not give, drawn as the solver would say it."""
    norm = math.hypot(*direction)
    return answer(s, 5).model_copy(
        update={
            "epipole2": None,
            "epipole2_h": (direction[0] / norm, direction[1] / norm, 0.0),
            "uncertainty": Uncertainty(ellipse=None),
        }
    )


@pytest.mark.parametrize(
    ("direction", "side"),
    [((1.0, 0.2), "right"), ((-1.0, 0.3), "left"), ((0.1, -1.0), "top")],
)
def test_friend1_at_infinity_gets_an_arrow_at_the_border_that_way(
    direction: tuple[float, float], side: str
) -> None:
    s = scene(2)
    norm = math.hypot(*direction)
    result = at_infinity(s, direction)
    photo = grey(s.image_size2)
    drawn = draw_overlay(photo, result)
    width, height = s.image_size2
    offsets = pixels(changed(photo, drawn)) - (width / 2, height / 2)
    along = offsets @ (np.array(direction) / norm)
    assert along.min() > 0  # everything on that side of the centre: arrow and its text
    arrow = pixels(painted(drawn, FRIEND_COLOUR_BGR))
    edge = {
        "right": arrow[:, 0].max() > width - diagonal(photo) / 15,
        "left": arrow[:, 0].min() < diagonal(photo) / 15,
        "top": arrow[:, 1].min() < diagonal(photo) / 15,
    }
    assert edge[side]


# --- four landmarks: the curve ----------------------------------------------------------


def curve_and_label(conic: np.ndarray, paint: np.ndarray, size: float) -> np.ndarray:
    """(H, W) mask of the painted pixels on the curve, after checking that the others are one
    label beside it: a compact block near the curve (its text), and nothing else."""
    found = pixels(paint)
    off = found[distance_to_conic(conic, found) >= size / 250]
    if len(off):
        width, height = np.ptp(off, axis=0)
        assert width < size / 3  # "friend on this curve", no more
        assert height < size / 20
        assert distance_to_conic(conic, off).min() < size / 8
    on_curve = found[distance_to_conic(conic, found) < size / 250].astype(int)
    mask = np.zeros(paint.shape, bool)
    mask[on_curve[:, 1], on_curve[:, 0]] = True
    return mask


def test_the_curve_of_four_landmarks_runs_through_them_and_the_true_friend() -> None:
    s = scene(0)
    result = answer(s, 4)
    assert result.method == "conic"
    assert result.conic2 is not None
    photo = grey(s.image_size2)
    drawn = draw_overlay(photo, result)
    conic = np.array(result.conic2)
    # Every painted pixel is on the curve (within the stroke's half width) or its label.
    paint = curve_and_label(conic, changed(photo, drawn), diagonal(photo))
    assert gap_to(paint, zero_crossings(conic, photo.shape)) < 1.5  # all of it, unbroken
    for landmark in s.landmarks2[:4]:
        assert near(paint, landmark, 2.0)
    assert near(paint, s.epipole2, 2.0)


@pytest.mark.parametrize(
    "conic",
    [
        # hyperbola (x - 800)(y - 600) = 40000: two branches in opposite quadrants
        [[0.0, 0.5, -300.0], [0.5, 0.0, -400.0], [-300.0, -400.0, 480000.0 - 40000.0]],
        # line pair (x - 400)(y - 300) = 0, crossing in the photo
        [[0.0, 0.5, -150.0], [0.5, 0.0, -200.0], [-150.0, -200.0, 120000.0]],
        # a circle of radius 1e6 px centred below the photo: its top runs along y = 600
        [[1.0, 0.0, -800.0], [0.0, 1.0, -1e6 - 600.0], [-800.0, -1e6 - 600.0, 1.20036e9 + 640000]],
    ],
    ids=["hyperbola", "line-pair", "huge-circle"],
)
def test_any_conic_is_drawn_on_itself(conic: list[list[float]]) -> None:
    s = scene(0)
    matrix = np.array(conic) / np.linalg.norm(conic)
    result = answer(s, 4).model_copy(update={"conic2": tuple(map(tuple, matrix))})
    photo = grey(s.image_size2)
    paint = curve_and_label(matrix, changed(photo, draw_overlay(photo, result)), diagonal(photo))
    crossings = zero_crossings(matrix, photo.shape)
    assert crossings.sum() > 1000
    assert gap_to(paint, crossings) < 1.5  # every branch and line, unbroken


# --- landmarks --------------------------------------------------------------------------


def test_a_landmark_has_the_same_colour_on_both_phones() -> None:
    s = scene(1)  # no landmark under the friend's marker, none under another's number
    labels = [1, 5, 12, 13, 7]  # 13 wraps round to 1's colour
    result = answer(s, 5)
    two = draw_overlay(grey(s.image_size2), result, points=s.landmarks2[:5], labels=labels)
    one = draw_overlay(grey(s.image_size1), result, photo=1, points=s.landmarks1[:5], labels=labels)
    for label, p, q in zip(labels, s.landmarks1[:5], s.landmarks2[:5], strict=True):
        assert at(two, q) == at(one, p) == landmark_colour(label)  # the centre dot
    assert landmark_colour(13) == landmark_colour(1)


def test_the_palette_is_distinct_and_the_web_gets_the_same_colours() -> None:
    assert len(LANDMARK_COLOURS_BGR) == len(LANDMARK_COLOURS_HEX) == 12
    for label in range(1, 30):
        b, g, r = landmark_colour(label)
        assert landmark_colour_hex(label) == f"#{r:02x}{g:02x}{b:02x}"
    colours = np.array(LANDMARK_COLOURS_BGR, float)
    gaps = np.linalg.norm(colours[:, None] - colours[None], axis=2)
    gaps[np.diag_indices(len(colours))] = np.inf
    assert gaps.min() > 60  # no two numbers look alike
    for reserved in (FRIEND_COLOUR_BGR, SUSPECT_COLOUR_BGR):
        assert np.linalg.norm(colours - reserved, axis=1).min() > 70


def test_a_mis_tapped_landmark_is_ringed_in_red() -> None:
    s = scene(1, 9)
    taps2 = s.landmarks2.copy()
    taps2[2] += (60.0, -45.0)  # landmark #3 tapped at the wrong spot in photo 2
    result = answer(s, 9, taps2=taps2)
    assert result.suspect_landmarks == [2]
    photo = grey(s.image_size2)
    size = diagonal(photo)
    red = painted(draw_overlay(photo, result, points=taps2), SUSPECT_COLOUR_BGR)
    assert near(red, taps2[2], size / 40)
    assert np.max(np.hypot(*(pixels(red) - taps2[2]).T)) < size / 40
    trusted = result.model_copy(update={"suspect_landmarks": []})
    assert not painted(draw_overlay(photo, trusted, points=taps2), SUSPECT_COLOUR_BGR).any()


def test_epipolar_lines_join_each_landmark_to_the_friend() -> None:
    s = scene(2)
    result = answer(s, 5)
    photo = grey(s.image_size2)
    landmarks = s.landmarks2[:5]
    plain = draw_overlay(photo, result, points=landmarks)
    lined = draw_overlay(photo, result, points=landmarks, epipolar_lines=True)
    extra = pixels(changed(plain, lined))
    e2 = np.array(result.epipole2)
    gaps = np.stack([distance_to_line(extra, q, q - e2) for q in landmarks])
    assert gaps.min(axis=0).max() < diagonal(photo) / 400  # every new pixel is on a line
    width, height = s.image_size2
    markers = np.vstack([landmarks, e2])
    for label, q in enumerate(landmarks, 1):
        # Points all along the line, on the photo and clear of every marker and number.
        steps = np.arange(-2000.0, 2000.0, 25.0)[:, None]
        along = q + steps * (q - e2) / np.hypot(*(q - e2))
        on_photo = np.all((along >= 2) & (along < (width - 2, height - 2)), axis=1)
        clear = np.min(np.hypot(*(along[:, None] - markers).transpose(2, 0, 1)), axis=1) > 100
        probes = along[on_photo & clear]
        assert len(probes) > 10
        colour = np.array(landmark_colour(label))
        hits = [
            np.abs(lined[round(y) - 1 : round(y) + 2, round(x) - 1 : round(x) + 2] - colour)
            .sum(axis=2)
            .min()
            < 40
            for x, y in probes
        ]
        assert np.mean(hits) > 0.9  # the line runs the whole way, in the landmark's colour


def test_epipolar_lines_are_parallel_when_the_friend_is_at_infinity() -> None:
    s, direction = scene(2), (1.0, 0.2)
    result = at_infinity(s, direction)
    photo = grey(s.image_size2)
    landmarks = s.landmarks2[:5]
    plain = draw_overlay(photo, result, points=landmarks)
    extra = pixels(
        changed(plain, draw_overlay(photo, result, points=landmarks, epipolar_lines=True))
    )
    gaps = np.stack([distance_to_line(extra, q, direction) for q in landmarks])
    assert len(extra) > 1000
    assert gaps.min(axis=0).max() < diagonal(photo) / 400


# --- photo 1: the friend tapped; other candidates -----------------------------------------


def test_photo_1_marks_the_tapped_friend_with_a_sight_that_keeps_them_visible() -> None:
    s = scene(2)
    result = answer(s, 5)
    photo = grey(s.image_size1)
    drawn = draw_overlay(photo, result, photo=1)
    e1 = np.array(result.epipole1)
    size = diagonal(photo)
    assert near(painted(drawn, FRIEND_COLOUR_BGR), e1, size / 30)
    assert np.max(np.hypot(*(pixels(changed(photo, drawn)) - e1).T)) < size / 30
    assert at(drawn, e1) == (GREY, GREY, GREY)  # open in the middle: the friend shows through


def test_other_positions_that_fit_are_shown_as_hollow_question_marks() -> None:
    s = scene(3)
    result = answer(s, 7, epipole1=None)
    assert result.method == "seven_point"
    others = [np.array(c.epipole2) for c in result.candidates if c.rank > 1]
    assert len(others) == 2
    photo = grey(s.image_size2)
    size = diagonal(photo)
    drawn = draw_overlay(photo, result)
    alone = draw_overlay(photo, result.model_copy(update={"candidates": []}))
    extra = changed(alone, drawn)
    friend = painted(drawn, FRIEND_COLOUR_BGR)
    for other in others:
        assert near(friend, other, size / 40)
        assert at(drawn, other) != FRIEND_COLOUR_BGR  # hollow
    # Nothing else: the answer's own candidate is in its frame already.
    gaps = np.stack([np.hypot(*(pixels(extra) - other).T) for other in others])
    assert gaps.min(axis=0).max() < size / 25


# --- size and robustness ----------------------------------------------------------------


def test_strokes_markers_and_text_grow_with_the_photo() -> None:
    s = scene(4, image_size=(1600, 1200), focal=1400.0)
    small = answer(s, 5)
    big = solve(
        2 * s.landmarks1[:5],
        2 * s.landmarks2[:5],
        epipole1=2 * s.epipole1,
        image_size1=(3200, 2400),
        image_size2=(3200, 2400),
        tap_sigma=4.0,  # the same fingers on a photo twice as fine
    )
    small_photo, big_photo = grey((1600, 1200)), grey((3200, 2400))
    small_paint = changed(small_photo, draw_overlay(small_photo, small, points=s.landmarks2[:5]))
    big_paint = changed(big_photo, draw_overlay(big_photo, big, points=2 * s.landmarks2[:5]))
    # Everything twice as big covers four times the pixels; fixed sizes would cover ~1-2x.
    # (the thinnest outline is 2 px at both sizes, so a little under four times)
    assert 3.0 < big_paint.sum() / small_paint.sum() < 4.8


def region(
    center: tuple[float, float], axes: tuple[float, float], angle_deg: float
) -> dict[str, Uncertainty]:
    """An answer's update to a 95 % region of this ``center``, ``axes`` and ``angle_deg``."""
    ellipse = Ellipse(center=center, axes=axes, angle_deg=angle_deg)
    return {"uncertainty": Uncertainty(ellipse=ellipse)}


@pytest.mark.parametrize(
    "update",
    [
        {"epipole2": (1e15, -3e14), "epipole2_h": (0.95, -0.3, 1e-15)},
        region((800, 600), (1e12, 0), 30),
        region((-1e9, 5e8), (3e9, 2e9), 1),
        region((800, 600), (0, 0), 0),
    ],
    ids=["far-friend1", "needle-ellipse", "huge-far-ellipse", "point-ellipse"],
)
def test_extreme_answers_are_drawn_without_overflow(update: dict[str, Any]) -> None:
    s = scene(2)
    result = answer(s, 5).model_copy(update=update)
    photo = grey(s.image_size2)
    drawn = draw_overlay(photo, result, points=s.landmarks2[:5], epipolar_lines=True)
    assert drawn.shape == photo.shape
    assert changed(photo, drawn).any()


def test_a_needle_thin_ellipse_is_drawn_as_its_long_axis() -> None:
    s = scene(2)
    needle = region((800.0, 600.0), (1e12, 0.0), 30.0)
    result = answer(s, 5).model_copy(update={"epipole2": (800.0, 600.0), **needle})
    photo = grey(s.image_size2)
    paint = changed(photo, draw_overlay(photo, result))
    axis = np.array([math.cos(math.radians(30)), math.sin(math.radians(30))])
    for reach in (-500.0, 400.0):
        assert near(paint, np.array([800.0, 600.0]) + reach * axis, 1.5)


# --- refusals ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("image", "code"),
    [
        (np.zeros((120, 160, 3), np.float32), ErrorCode.INVALID_SHAPE),
        (np.zeros((120, 160, 4), np.uint8), ErrorCode.INVALID_SHAPE),
        (np.zeros((120,), np.uint8), ErrorCode.INVALID_SHAPE),
        (np.zeros((0, 160, 3), np.uint8), ErrorCode.INVALID_SHAPE),
        ([[0, 0], [0, 0]], ErrorCode.INVALID_SHAPE),
    ],
    ids=["float", "four-channels", "one-dimensional", "empty", "list"],
)
def test_a_photo_that_is_not_an_8_bit_image_is_refused(image: Any, code: ErrorCode) -> None:
    with pytest.raises(SolverError) as refused:
        draw_overlay(image, answer(scene(2), 5))
    assert refused.value.code == code


@pytest.mark.parametrize(
    ("keywords", "code"),
    [
        ({"points": [[1.0, 2.0, 3.0]]}, ErrorCode.INVALID_SHAPE),
        ({"points": [[1.0, math.nan]]}, ErrorCode.NOT_FINITE),
        ({"points": [[1.0, 2.0], [3.0, 4.0]], "labels": [1]}, ErrorCode.MISMATCHED_LENGTHS),
        ({"labels": [1, 2]}, ErrorCode.MISMATCHED_LENGTHS),
        ({"photo": 3}, ErrorCode.INVALID_PARAMETER),
    ],
    ids=["three-columns", "nan", "too-few-labels", "labels-without-points", "unknown-photo"],
)
def test_bad_landmarks_or_options_are_refused(keywords: dict[str, Any], code: ErrorCode) -> None:
    with pytest.raises(SolverError) as refused:
        draw_overlay(grey((160, 120)), answer(scene(2), 5), **keywords)
    assert refused.value.code == code


# --- a real photo -----------------------------------------------------------------------


def test_the_temple_photos_get_the_answer_and_numbered_landmarks() -> None:
    s = temple_scene(
        TEMPLE / "templeSR_par.txt", "templeSR0003", "templeSR0006", 5, np.random.default_rng(7)
    )
    result = solved(s)
    assert result.epipole2 is not None
    photo2 = cv2.imread(str(TEMPLE / "templeSR0006.png"))
    photo1 = cv2.imread(str(TEMPLE / "templeSR0003.png"))
    assert photo2 is not None
    assert photo1 is not None
    two = draw_overlay(photo2, result, points=s.landmarks2)
    one = draw_overlay(photo1, result, photo=1, points=s.landmarks1)
    assert two.shape == photo2.shape == (480, 640, 3)
    assert two.dtype == one.dtype == np.uint8
    assert at(two, result.epipole2) == at(photo2, result.epipole2)  # the friend shows
    assert near(painted(two, FRIEND_COLOUR_BGR), np.array(result.epipole2), diagonal(two) / 25)
    for label, (p, q) in enumerate(zip(s.landmarks1, s.landmarks2, strict=True), 1):
        assert at(two, q) == at(one, p) == landmark_colour(label)
