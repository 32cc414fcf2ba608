"""Turning caller input into clean arrays, and refusing what cannot be answered.

Every check raises :class:`SolverError` with a stable code. Tolerances are in pixels: the
exact solvers use a tiny one relative to the image spread (exact degeneracy), ``solve``
uses the tap noise (degenerate at the precision of a finger).

Lengths are a photo's pixels, within the range a double holds together with their squares
and fourth powers (covariances, and F's covariance, which goes as the fourth power of the
pixel scale): a position within :data:`LARGEST_PX` of the origin, a photo's side and a tap's
sigma between :data:`FINEST_PX` and :data:`LARGEST_PX`. Beyond them the arithmetic
over- or underflows (a landmark at 1e300 px made the Hartley normaliser singular), so they
are refused with ``invalid_parameter``, never answered with a 500 or a NaN.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from .errors import Marks, Reason
from .projective import FAR_AWAY_PX, Array
from .refusal import SolverError

Photo = Literal[1, 2]

MAX_LANDMARKS = 256
# Relative tolerance for exact degeneracy: far below any tap, far above float rounding.
EXACT_TOLERANCE = 1e-9
# The farthest a position may be from the origin, px: a tenth of where a point counts as at
# infinity (FAR_AWAY_PX). The largest photos ever made are about 1e5 px a side.
LARGEST_PX = FAR_AWAY_PX / 10
# The finest precision (a tap's sigma) and the smallest photo side, px: a millionth of a
# pixel, far finer than any finger, and still 1e-12 of LARGEST_PX, which a double resolves
# (its 16 digits leave 4 to spare).
FINEST_PX = 1e-6
# How much sharper a tap may be along one axis than along the other (ratio of its sigmas):
# beyond it, its covariance is too near singular for its Cholesky factor to be exact
# (condition 1e8, where a double resolves 1e16).
MOST_ELONGATED = 1e4
# A gravity reading's sigma, degrees: finer than any phone's accelerometer (about 0.1) down
# to one that says nothing (a reading 30 degrees off is no reading).
FINEST_DEG = 0.01
LARGEST_DEG = 30.0
# A compass heading's sigma may be larger: steel stadiums bend compasses by tens of degrees,
# and a phone that says so still narrows the turn about the vertical.
LARGEST_HEADING_DEG = 90.0


def _array(value: ArrayLike, name: str) -> Array:
    try:
        array = np.asarray(value, dtype=np.float64)
    except OverflowError as error:  # an integer beyond a float's range (JSON has them)
        raise SolverError(Reason.BEYOND_FLOATS, field=name) from error
    except (TypeError, ValueError) as error:
        raise SolverError(Reason.NOT_A_NUMBER, field=name) from error
    if not np.isfinite(array).all():
        raise SolverError(Reason.NOT_FINITE, field=name)
    return array


def _near(array: Array, name: str) -> Array:
    """``array`` of pixel positions, refused when one is beyond :data:`LARGEST_PX`."""
    if array.size and float(np.abs(array).max()) > LARGEST_PX:
        raise SolverError(Reason.TOO_FAR, field=name, largest_px=LARGEST_PX)
    return array


def points(value: ArrayLike, name: str) -> Array:
    """(N, 2) float array of pixel points, finite, within :data:`LARGEST_PX`; an empty list
    is none, (0, 2)."""
    array = _array(value, name)
    if array.shape == (0,):
        return array.reshape(0, 2)
    if array.ndim != 2 or array.shape[1] != 2:
        raise SolverError(Reason.NOT_POINTS, field=name, shape=array.shape)
    return _near(array, name)


def point(value: ArrayLike, name: str) -> Array:
    """(3,) homogeneous point from a (2,) pixel point or a (3,) homogeneous one."""
    array = _array(value, name)
    if array.shape == (2,):
        return np.append(array, 1.0)
    if array.shape == (3,) and np.any(array != 0):
        return array
    raise SolverError(Reason.NOT_A_POINT, field=name)


def pixel(value: ArrayLike, name: str) -> Array:
    """(2,) pixel position of a tap, finite, within :data:`LARGEST_PX`."""
    array = _array(value, name)
    if array.shape != (2,):
        raise SolverError(Reason.NOT_A_PIXEL, field=name)
    return _near(array, name)


def line(value: ArrayLike, name: str) -> Array:
    """(3,) line (a, b, c) meaning a x + b y + c = 0, with (a, b) not both zero, scaled to
    ``a^2 + b^2 = 1`` (the same line: ``c`` is then its distance from the origin, px),
    refused when farther than :data:`LARGEST_PX`."""
    array = _array(value, name)
    if array.shape != (3,) or not np.any(array[:2] != 0):
        raise SolverError(Reason.NOT_A_LINE, field=name)
    # In two steps, so that neither a subnormal nor a huge (a, b) over- or underflows.
    with np.errstate(over="ignore"):
        array = array / float(np.abs(array[:2]).max())
        array = array / math.hypot(array[0], array[1])
    if not abs(array[2]) <= LARGEST_PX:
        raise SolverError(Reason.TOO_FAR, field=name, largest_px=LARGEST_PX)
    return array


def direction(value: ArrayLike, name: str) -> Array:
    """(3,) unit vector from any finite, nonzero (3,) vector (a phone's gravity reading)."""
    array = _array(value, name)
    if array.shape != (3,) or not np.any(array != 0):
        raise SolverError(Reason.NOT_A_DIRECTION, field=name)
    # In two steps, so that neither a subnormal nor a huge vector over- or underflows.
    array = array / float(np.abs(array).max())
    unit: Array = array / math.sqrt(float(array @ array))
    return unit


def angle(value: float, name: str, largest: float = LARGEST_DEG) -> float:
    """A sensor's sigma in degrees, between :data:`FINEST_DEG` and ``largest``."""
    number = positive(value, name)
    if FINEST_DEG <= number <= largest:
        return number
    raise SolverError(Reason.NOT_AN_ANGLE, field=name, finest_deg=FINEST_DEG, largest_deg=largest)


def heading(value: float, name: str) -> float:
    """A compass heading in degrees (any finite number: 370 is 10), as radians in
    [0, 2 pi)."""
    array = _array(value, name)
    if array.shape != ():
        raise SolverError(Reason.NOT_A_NUMBER, field=name)
    return math.radians(float(array) % 360.0)


def positive(value: float, name: str) -> float:
    """A finite, strictly positive number."""
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError) as error:
        raise SolverError(Reason.NOT_POSITIVE, field=name) from error
    if not math.isfinite(number) or number <= 0:
        raise SolverError(Reason.NOT_POSITIVE, field=name)
    return number


def length(value: float, name: str) -> float:
    """A sigma or a side in px: positive, between :data:`FINEST_PX` and :data:`LARGEST_PX`."""
    number = positive(value, name)
    if not FINEST_PX <= number <= LARGEST_PX:
        raise SolverError(
            Reason.NOT_A_LENGTH, field=name, finest_px=FINEST_PX, largest_px=LARGEST_PX
        )
    return number


def image_size(value: ArrayLike | None, name: str) -> tuple[float, float] | None:
    """(width, height) in pixels, both positive (between :data:`FINEST_PX` and
    :data:`LARGEST_PX`), or None."""
    if value is None:
        return None
    array = _array(value, name)
    if array.shape != (2,) or (array <= 0).any():
        raise SolverError(Reason.NOT_A_SIZE, field=name)
    return length(float(array[0]), name), length(float(array[1]), name)


def spread(pts: Array) -> float:
    """Typical size of a point set in pixels (its bounding-box diagonal, at least 1)."""
    width, height = (pts.max(axis=0) - pts.min(axis=0)).tolist()
    return max(math.hypot(width, height), 1.0)


def landmark_pairs(
    points1: ArrayLike,
    points2: ArrayLike,
    *,
    minimum: int,
    maximum: int = MAX_LANDMARKS,
    marked: Marks | None = None,
    tolerance: float | None = None,
    labels: Sequence[int] | None = None,
    epipole1: Array | None = None,
    epipole2: Array | None = None,
    directions: bool = True,
) -> tuple[Array, Array]:
    """Both photos' landmarks as (N, 2) arrays, refused when they cannot determine anything.

    Args:
        points1, points2: (N, 2) landmarks in photo 1 and photo 2, same order.
        minimum, maximum: how many landmarks the caller's method takes.
        marked: how the friends were marked (what sets ``minimum``), said in the refusal
            of too few; None: a solver of its own ('needed here').
        tolerance: distance in pixels below which two taps count as the same place; by
            default an exact (relative) tolerance.
        labels: the landmark numbers a person sees, for messages (default 1..N).
        epipole1, epipole2: (3,) homogeneous epipoles when known, checked against the
            landmarks of their photo.
        directions: whether the landmarks must spread around each epipole (not all on one
            line through it). Two calibrated cameras that see each other need no more than
            one landmark, which is always on such a line.
    """
    p, q = points(points1, "points1"), points(points2, "points2")
    if len(p) != len(q):
        raise SolverError(Reason.MISMATCHED_LENGTHS, counts=(len(p), len(q)))
    if len(p) < minimum:
        if marked is None:
            raise SolverError(Reason.TOO_FEW_LANDMARKS, count=len(p), minimum=minimum)
        raise SolverError(Reason.TOO_FEW_LANDMARKS, count=len(p), minimum=minimum, marked=marked)
    if len(p) > maximum:
        raise SolverError(Reason.TOO_MANY_LANDMARKS, count=len(p), maximum=maximum)
    names = list(labels) if labels is not None else list(range(1, len(p) + 1))
    photos: tuple[tuple[Photo, Array, Array | None], ...] = ((1, p, epipole1), (2, q, epipole2))
    for photo, pts, epipole in photos if len(p) else ():
        tol = tolerance if tolerance is not None else EXACT_TOLERANCE * spread(pts)
        _refuse_repeats(pts, tol, photo, names)
        if epipole is not None:
            _refuse_epipole(epipole, pts, tol, photo, names, spread_needed=directions)
        if len(pts) >= 3 and _off_line_spread(pts) <= tol:
            raise SolverError(Reason.COLLINEAR_LANDMARKS, photo=photo)
    return p, q


def _refuse_repeats(pts: Array, tol: float, photo: Photo, names: Sequence[int]) -> None:
    if len(pts) < 2:
        return
    offsets = pts[:, None, :] - pts[None, :, :]
    gaps = np.hypot(offsets[..., 0], offsets[..., 1])
    gaps.flat[:: len(pts) + 1] = np.inf
    i, j = divmod(int(gaps.argmin()), len(pts))
    if gaps[i, j] <= tol:
        first, second = sorted((i, j))
        raise SolverError(
            Reason.REPEATED_LANDMARKS, landmarks=(names[first], names[second]), photo=photo
        )


def _off_line_spread(pts: Array) -> float:
    """Largest distance (px) of a point from the best-fitting line through all of them.

    The line is the scatter's major axis, at half the angle of ``(2 s_xy, s_xx - s_yy)``
    (the closed form of the 2x2 eigenvector, cheaper than an SVD on every solve).
    """
    centred = pts - np.add.reduce(pts, axis=0) / len(pts)
    (s_xx, s_xy), (_, s_yy) = (centred.T @ centred).tolist()
    angle = 0.5 * math.atan2(2.0 * s_xy, s_xx - s_yy)
    off_line = centred[:, 1] * math.cos(angle) - centred[:, 0] * math.sin(angle)
    return float(np.abs(off_line).max())


def _refuse_epipole(
    epipole: Array,
    pts: Array,
    tolerance: float,
    photo: Photo,
    names: Sequence[int],
    *,
    spread_needed: bool,
) -> None:
    """Refuse an epipole tapped on a landmark, or (``spread_needed``) landmarks all on one
    line through it."""
    if abs(epipole[2]) > 0:
        at = epipole[:2] / epipole[2]
        directions = pts - at
        distances = np.hypot(directions[:, 0], directions[:, 1])
        closest = int(distances.argmin())
        if distances[closest] <= tolerance:
            raise SolverError(Reason.EPIPOLE_ON_LANDMARK, landmark=names[closest], photo=photo)
        if not spread_needed:
            return
        # Each landmark's distance from the line through the epipole and the farthest landmark.
        far = int(distances.argmax())
        (x, y), length = directions[far].tolist(), float(distances[far])
        off_line = float(np.abs(directions[:, 1] * x - directions[:, 0] * y).max()) / length
    elif not spread_needed:
        return
    else:  # epipole at infinity: the epipolar lines are parallel to its direction
        normal = np.array([-epipole[1], epipole[0]]) / np.hypot(epipole[0], epipole[1])
        off_line = float(np.ptp(pts @ normal))
    if off_line <= tolerance:
        raise SolverError(Reason.LANDMARKS_ON_EPIPOLAR_LINE, photo=photo)


def covariances(value: ArrayLike | None, count: int, default: float, name: str) -> Array:
    """(count, 2, 2) tap covariances, px^2, from one sigma per tap (count,) or one 2x2
    covariance per tap (count, 2, 2); ``default`` px for every tap when None."""
    if value is None:
        round_ = np.zeros((count, 2, 2))
        round_[:, 0, 0] = round_[:, 1, 1] = default**2
        return round_
    array = _array(value, name)
    if array.shape == (count,):
        for sigma in array.tolist():
            length(sigma, name)
        return array[:, None, None] ** 2 * np.eye(2)
    if array.shape == (count, 2, 2):
        return _positive_definite(array, name)
    raise SolverError(Reason.NOT_PRECISIONS, field=name, count=count)


def covariance(value: ArrayLike | None, default: float, name: str) -> Array:
    """(2, 2) covariance of one tap, px^2, from a sigma or a 2x2 covariance."""
    if value is None:
        return default**2 * np.eye(2)
    array = _array(value, name)
    if array.shape == ():
        return length(float(array), name) ** 2 * np.eye(2)
    if array.shape == (2, 2):
        return _positive_definite(array[None], name)[0]
    raise SolverError(Reason.NOT_A_PRECISION, field=name)


def _positive_definite(array: Array, name: str) -> Array:
    """(N, 2, 2) symmetric positive-definite covariances whose sigmas (square roots of the
    eigenvalues) are between :data:`FINEST_PX` and :data:`LARGEST_PX`, at most
    :data:`MOST_ELONGATED` times apart; or a refusal."""
    with np.errstate(over="ignore", invalid="ignore"):
        symmetric = np.allclose(array, array.transpose(0, 2, 1), rtol=1e-9, atol=0.0)
        array = (array + array.transpose(0, 2, 1)) / 2.0
        a, b, c = array[:, 0, 0], array[:, 0, 1], array[:, 1, 1]
        # The 2x2 eigenvalues in closed form; the small one from the determinant (no
        # cancellation), which is only trusted once the large one is within bounds.
        largest = a / 2.0 + c / 2.0 + np.hypot(a / 2.0 - c / 2.0, b)
        smallest = (a * c - b * b) / largest
    if not symmetric or not np.all((a > 0) & (smallest > 0)):
        raise SolverError(Reason.NOT_A_COVARIANCE, field=name)
    if not np.all(
        (largest <= LARGEST_PX**2)
        & (smallest >= FINEST_PX**2)
        & (smallest * MOST_ELONGATED**2 >= largest)
    ):
        raise SolverError(
            Reason.NOT_A_USABLE_COVARIANCE,
            field=name,
            finest_px=FINEST_PX,
            largest_px=LARGEST_PX,
            most_elongated=MOST_ELONGATED,
        )
    return array
