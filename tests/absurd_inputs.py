"""Hypothesis strategies for whatever a caller may send the solver: the corners a uniform
random draw never reaches.

A random draw of taps (``tests/solver/test_absurd_input.py``: normals times 10^-3 to 10^8)
meets neither 1e300 nor a subnormal, and never three landmarks exactly on one line, two a
hair apart or all on one plane: each has probability zero. These strategies draw them on
purpose, from a real two-camera scene (``testbed.scenes``) scaled by any power of ten a
float holds, with none, one or two of its parts bent into a corner (``CORNERS``). With the
suite's profile (``tests/conftest.py``) Hypothesis draws the same examples on every run.
"""

from __future__ import annotations

import math
import sys
from typing import Any

import numpy as np
from hypothesis import settings
from hypothesis import strategies as st

from shared_solver import Camera
from shared_solver.validation import FINEST_PX, LARGEST_PX, MOST_ELONGATED
from testbed.scenes import Scene, facing_scene

LARGEST = sys.float_info.max
SMALLEST = 5e-324  # the smallest subnormal
# Magnitudes where something changes: subnormals, the normal range's ends, where a square or
# a fourth power overflows or underflows (1e154, 1e77), where a double's 16 digits run out.
EDGE_MAGNITUDES = (
    SMALLEST,
    sys.float_info.min,
    1e-300,
    1e-160,
    1e-80,
    1e-8,
    1e-3,
    1.0,
    1e3,
    1e8,
    1e16,
    1e80,
    1e160,
    1e300,
    LARGEST,
)


def examples(in_the_suite: int) -> int:
    """How many examples a property test draws: its share of the suite's time, or ten times
    as many when exploring (``HYPOTHESIS_PROFILE=explore``, tests/conftest.py)."""
    return in_the_suite * (10 if settings.get_current_profile_name() == "explore" else 1)


# Any finite float, the extremes and subnormals included (Hypothesis draws them often).
any_float = st.floats(allow_nan=False, allow_infinity=False)
# Anything JSON or Python may hold for a number: NaN, infinities, integers beyond a float.
any_number = st.floats() | st.integers(-(2**70), 2**70) | st.sampled_from([10**400, -(10**400)])

# A scene is a 1600 x 1200 px photo tapped at 2 px: scaled by these it stays within what the
# solver honours (its finest sigma and its farthest position), and at their ends it touches
# them.
SMALLEST_SCENE_SCALE = FINEST_PX / 2.0
LARGEST_SCENE_SCALE = LARGEST_PX / 2000.0


@st.composite
def magnitudes(draw: st.DrawFn) -> float:
    """A positive scale: any power of ten a float holds, from subnormals to the largest."""
    if draw(st.booleans()):
        return draw(st.sampled_from(EDGE_MAGNITUDES))
    mantissa = draw(st.floats(1.0, 9.99))
    return mantissa * 10.0 ** draw(st.integers(-323, 307))


@st.composite
def scene_scales(draw: st.DrawFn) -> float:
    """How much a scene is scaled: mostly within what the solver honours (at its ends, often),
    else any magnitude."""
    how = draw(st.sampled_from(["honoured", "honoured", "ends", "any"]))
    if how == "honoured":
        low, high = math.log10(SMALLEST_SCENE_SCALE), math.log10(LARGEST_SCENE_SCALE)
        return 10.0 ** draw(st.floats(low, high))
    if how == "ends":
        return draw(st.sampled_from([SMALLEST_SCENE_SCALE, LARGEST_SCENE_SCALE]))
    return draw(magnitudes())


def scenes(planar: bool | None = None) -> st.SearchStrategy[Scene]:
    """Two phones facing each other across a venue, 1 to 12 landmarks (mostly 3 or more); on
    the floor (one plane) when ``planar``, drawn either way when None."""
    return st.builds(
        lambda seed, count, flat: facing_scene(np.random.default_rng(seed), count, planar=flat),
        st.integers(0, 2**32 - 1),
        st.sampled_from([1, 2, 3, 3, 4, 4, 5, 5, 6, 7, 8, 12]),
        st.booleans() if planar is None else st.just(planar),
    )


def _scaled(points: np.ndarray, scale: float, offset: np.ndarray) -> np.ndarray:
    with np.errstate(all="ignore"):  # an overflow to inf is part of the draw: refused
        return np.asarray(points * scale + offset)


@st.composite
def _offsets(draw: st.DrawFn, scale: float, anywhere: bool) -> np.ndarray:
    """Where the scaled scene sits: at the origin, near it, or (``anywhere``) at any float."""
    kinds = ["origin", "scaled", "honoured"] + (["any"] * 3 if anywhere else [])
    how = draw(st.sampled_from(kinds))
    if how == "origin":
        return np.zeros(2)
    if how == "honoured":
        return np.array(draw(st.tuples(*[st.floats(-LARGEST_PX / 10, LARGEST_PX / 10)] * 2)))
    if how == "scaled":
        steps = draw(st.tuples(st.floats(-10, 10), st.floats(-10, 10)))
        with np.errstate(all="ignore"):
            return scale * np.array(steps)
    return np.array(draw(st.tuples(any_float, any_float)))


def _bend(draw: st.DrawFn, bend: str, points: np.ndarray, sigma: float) -> np.ndarray:
    """``points`` bent into a corner: two made near-duplicates (a fraction of a tap sigma
    apart, or a few float steps), all put on one line (exactly, or off it by a hair), or
    all replaced by any floats."""
    points = points.copy()
    count = len(points)
    if bend == "near_duplicate" and count >= 2:
        i, j = draw(st.lists(st.integers(0, count - 1), min_size=2, max_size=2, unique=True))
        gap = draw(
            st.sampled_from([0.0, 0.49 * sigma, 0.51 * sigma, 2.0 * sigma])
            | st.builds(lambda k: k * _float_step(points[i]), st.integers(1, 4))
        )
        with np.errstate(all="ignore"):
            points[j] = points[i] + gap * np.array([math.cos(1.0), math.sin(1.0)])
        return points
    if bend == "collinear":
        start = points[0]
        with np.errstate(all="ignore"):
            direction = points[-1] - start if count > 1 else np.array([1.0, 2.0])
            steps = np.array(draw(st.lists(st.floats(-2, 2), min_size=count, max_size=count)))
            off = draw(st.sampled_from([0.0, 0.0, 0.4 * sigma, 3.0 * sigma]))
            normal = np.array([-direction[1], direction[0]])
            length = np.hypot(*normal)
            normal = normal / length if length > 0 else np.array([0.0, 1.0])
            return np.asarray(
                start + steps[:, None] * direction + off * (steps % 1.0)[:, None] * normal
            )
    if bend == "landmarks_anywhere":
        flat = draw(st.lists(any_float, min_size=2 * count, max_size=2 * count))
        return np.array(flat).reshape(count, 2)
    return points


def _float_step(point: np.ndarray) -> float:
    """The gap between adjacent floats at the larger coordinate of ``point``."""
    with np.errstate(all="ignore"):
        return float(np.spacing(np.abs(point).max()))


def sizes() -> st.SearchStrategy[Any]:
    """A photo's (width, height): absent, any positive size, or malformed."""
    positive = st.floats(min_value=SMALLEST, max_value=LARGEST) | magnitudes()
    return st.one_of(
        st.none(),
        st.tuples(positive, positive).map(list),
        st.tuples(any_number, any_number).map(list),
        st.lists(st.floats(1, 5000), min_size=0, max_size=3),
        st.just("large"),
    )


@st.composite
def cameras(draw: st.DrawFn) -> Any:
    """Every way of saying what a camera is, absurd focal lengths and malformed ones included."""
    return draw(
        st.one_of(
            st.sampled_from([None, "phone", "unknown", Camera.phone(), {"kind": "phone"}]),
            st.builds(
                lambda focal, uncertainty: {
                    "kind": "known_focal",
                    "focal_35mm": focal,
                    "focal_uncertainty": uncertainty,
                },
                st.floats(SMALLEST, 2000.0) | magnitudes() | any_number,
                st.sampled_from([SMALLEST, 1e-300, 1e-12, 1e-6, 0.02, 1.0])
                | st.floats(SMALLEST, 1.0),
            ),
            st.sampled_from(
                [
                    "zoomed",
                    42,
                    [26.0],
                    {"kind": "known_focal"},
                    {"kind": "phone", "focal_35mm": 26.0},
                    {"kind": "fisheye"},
                    {"kind": "phone", "lens": "wide"},
                ]
            ),
        )
    )


@st.composite
def covariance_matrices(draw: st.DrawFn, scale: float) -> list[list[float]]:
    """A 2x2 covariance: round, elongated (up to the solver's limit and beyond, turned at any
    angle), singular, negative, or any floats."""
    how = draw(st.sampled_from(["round", "elongated", "singular", "negative", "any"]))
    variance = scale * scale
    if how == "round":
        return [[variance, 0.0], [0.0, variance]]
    if how == "elongated":
        ratio = draw(st.sampled_from([10.0, MOST_ELONGATED, MOST_ELONGATED * 1.01]) | magnitudes())
        turn = draw(st.sampled_from([0.0, math.pi / 4]) | st.floats(0.0, math.pi))
        c, s = math.cos(turn), math.sin(turn)
        with np.errstate(all="ignore"):
            axes = np.diag([variance * ratio, variance / ratio])
            rotation = np.array([[c, -s], [s, c]])
            return (rotation @ axes @ rotation.T).tolist()
    if how == "singular":
        return [[variance, variance], [variance, variance]]
    if how == "negative":
        return [[-variance, 0.0], [0.0, variance]]
    return [[draw(any_float), draw(any_float)], [draw(any_float), draw(any_float)]]


@st.composite
def tap_precisions(draw: st.DrawFn, count: int) -> Any:
    """``points*_sigma``: absent, one sigma per tap, one covariance per tap, or the wrong shape."""
    how = draw(st.sampled_from(["none", "sigmas", "covariances", "wrong"]))
    if how == "none":
        return None
    scale = draw(magnitudes() | st.floats(0.5, 10.0))
    if how == "sigmas":
        return draw(
            st.lists(st.just(scale) | any_float, min_size=count, max_size=count)
            | st.just([scale] * count)
        )
    if how == "covariances":
        matrix = draw(covariance_matrices(scale))
        return [matrix] * count
    return draw(st.sampled_from([[scale] * (count + 1), scale, [[scale, scale]] * count]))


@st.composite
def mark_precisions(draw: st.DrawFn) -> Any:
    """``epipole*_sigma``: absent, a sigma, a covariance, or the wrong shape."""
    how = draw(st.sampled_from(["none", "sigma", "covariance", "wrong"]))
    if how == "none":
        return None
    scale = draw(magnitudes() | st.floats(0.5, 10.0) | any_number)
    if how == "sigma":
        return scale
    if how == "covariance":
        return draw(covariance_matrices(_finite(scale)))
    return [scale, scale, scale]


def _finite(number: float) -> float:
    """``|number|`` as a float, or 1 when it is none (NaN, infinite, an integer beyond floats)."""
    try:
        magnitude = abs(float(number))
    except OverflowError:
        return 1.0
    return magnitude if math.isfinite(magnitude) else 1.0


def _line_through(point: np.ndarray, angle: float) -> list[float]:
    """(a, b, c) of the line through ``point`` at ``angle`` radians."""
    a, b = -math.sin(angle), math.cos(angle)
    with np.errstate(all="ignore"):
        return [a, b, float(-(a * point[0] + b * point[1]))]


# The ways a request may be bent into a corner; a request takes none, one or two of them.
CORNERS = (
    "offset_anywhere",
    "near_duplicate",
    "collinear",
    "landmarks_anywhere",
    "marks_anywhere",
    "marks_conflicting",
    "photo_size",
    "camera",
    "tap_sigma",
    "tap_precisions",
    "mark_precisions",
)


@st.composite
def solve_requests(draw: st.DrawFn) -> dict[str, Any]:
    """The keyword arguments of ``solve`` (``points1`` and ``points2`` among them): a scene's
    taps scaled into any magnitude, with none, one or two of its parts bent into a corner."""
    scene = draw(scenes())
    scale = draw(scene_scales())
    corners = set(draw(st.lists(st.sampled_from(CORNERS), max_size=2, unique=True)))
    anywhere = "offset_anywhere" in corners
    offset1, offset2 = draw(_offsets(scale, anywhere)), draw(_offsets(scale, anywhere))
    tap_sigma: Any = 2.0 * scale if draw(st.booleans()) else 2.0
    if "tap_sigma" in corners:
        tap_sigma = draw(magnitudes() | st.floats(0.5, 10) | any_number)
    sigma = _finite(tap_sigma)
    points1 = _scaled(scene.landmarks1, scale, offset1)
    points2 = _scaled(scene.landmarks2, scale, offset2)
    bends = [b for b in ("near_duplicate", "collinear", "landmarks_anywhere") if b in corners]
    if bends:
        which = draw(st.sampled_from(["points1", "points2", "both"]))
        if which in ("points1", "both"):
            points1 = _bend(draw, bends[0], points1, sigma)
        if which in ("points2", "both"):
            points2 = _bend(draw, bends[0], points2, sigma)
    request: dict[str, Any] = {"points1": points1.tolist(), "points2": points2.tolist()}
    epipoles = _scaled(scene.epipole1, scale, offset1), _scaled(scene.epipole2, scale, offset2)
    request |= draw(_marks(corners, *epipoles))
    for name, size in (("image_size1", scene.image_size1), ("image_size2", scene.image_size2)):
        with np.errstate(all="ignore"):
            request[name] = (np.array(size, dtype=float) * scale).tolist()
        if "photo_size" in corners:
            request[name] = draw(st.just(request[name]) | sizes())
    request |= draw(_cameras("camera" in corners))
    request |= {"tap_sigma": tap_sigma, "fundamental_covariance": draw(st.booleans())}
    if "tap_precisions" in corners:
        request["points1_sigma"] = draw(tap_precisions(len(points1)))
        request["points2_sigma"] = draw(tap_precisions(len(points2)))
    if "mark_precisions" in corners:
        request["epipole1_sigma"] = draw(mark_precisions())
        request["epipole2_sigma"] = draw(mark_precisions())
    return request


@st.composite
def _marks(
    draw: st.DrawFn, corners: set[str], epipole1: np.ndarray, epipole2: np.ndarray
) -> dict[str, Any]:
    """How the friends are marked: friend 2 in photo 1 (a point or a line through it), both,
    or neither; with ``corners``, anywhere, or in conflicting ways."""
    marks = draw(st.sampled_from(["epipole1", "epipole1", "both", "line", "none"]))
    if "marks_conflicting" in corners:
        marks = draw(st.sampled_from(["epipole2 alone", "point and line"]))
    bent = "marks_anywhere" in corners
    anywhere = st.tuples(any_float, any_float).map(list)
    drawn: dict[str, Any] = {}
    if marks in ("epipole1", "both", "point and line"):
        drawn["epipole1"] = draw(anywhere) if bent else epipole1.tolist()
    if marks in ("both", "epipole2 alone"):
        drawn["epipole2"] = draw(anywhere) if bent else epipole2.tolist()
    if marks in ("line", "point and line"):
        drawn["epipolar_line1"] = (
            draw(st.lists(any_float, min_size=3, max_size=3))
            if bent
            else _line_through(epipole1, draw(st.floats(0, math.pi)))
        )
    return drawn


@st.composite
def _cameras(draw: st.DrawFn, any_kind: bool) -> dict[str, Any]:
    """``camera1`` and ``camera2``: two phones, a known focal length, unknown, or (``any_kind``)
    anything :func:`cameras` draws."""
    kind = draw(st.sampled_from(["phone", "phone", "unknown", None, "known_focal"]))
    camera1: Any = {"kind": "known_focal", "focal_35mm": 26.0} if kind == "known_focal" else kind
    camera2: Any = camera1
    if any_kind:
        camera1 = draw(cameras())
        camera2 = draw(st.just(camera1) | cameras())
    return {"camera1": camera1, "camera2": camera2}
