"""Small helpers of projective geometry in the plane.

Points are homogeneous 3-vectors ``(x, y, w)``; pixel points are ``(x, y)`` with x right and
y down (OpenCV's convention). Nothing here divides by ``w`` without checking it.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import linalg
from .linalg import Array

__all__ = [
    "FAR_AWAY_PX",
    "Array",  # defined with the linear algebra, which this module builds on
    "Indices",
    "Mask",
    "canonical",
    "canonical_matrix",
    "far_pixel",
    "hartley_normaliser",
    "homogeneous",
    "inside",
    "left_epipole",
    "orthogonal_complement",
    "right_epipole",
    "skew",
    "to_pixel",
    "transform",
    "unit",
]

Mask = NDArray[np.bool_]
Indices = NDArray[np.intp]

# A homogeneous point whose pixel position exceeds this many pixels is treated as lying at
# infinity: no phone photo is anywhere near that large.
FAR_AWAY_PX = 1e7


def homogeneous(points: Array) -> Array:
    """(N, 2) pixel points -> (N, 3) homogeneous points with w = 1."""
    stacked = np.ones((len(points), 3))
    stacked[:, :2] = points
    return stacked


def unit(vector: Array) -> Array:
    """The vector scaled to unit Euclidean norm (homogeneous quantities are up to scale)."""
    return vector / linalg.norm(vector)


def to_pixel(point: Array) -> Array | None:
    """(3,) homogeneous -> (2,) pixel point, or None when the point is (practically) at infinity."""
    w = point[2]
    if abs(w) * FAR_AWAY_PX <= max(abs(point[0]), abs(point[1])):
        return None
    return point[:2] / w


def far_pixel(point: Array) -> Array | None:
    """(3,) homogeneous -> (2,) pixel point however far it is; None only where it has none
    (w = 0, or not finite). For choices that must not depend on the photo's scale: past
    ``FAR_AWAY_PX`` a point is drawn as an arrow (:func:`to_pixel`), but a photo scaled up
    500 times moves points past it that the unscaled photo keeps."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        pixel = point[:2] / point[2]
    return pixel if bool(np.all(np.isfinite(pixel))) else None


def inside(points: Array, size: tuple[float, float]) -> Mask:
    """Which of the (N, 2) pixel points lie in a photo of ``size`` (width, height), edges
    included; NaN points do not."""
    width, height = size
    with np.errstate(invalid="ignore"):
        return (
            (points[:, 0] >= 0.0)
            & (points[:, 0] <= width)
            & (points[:, 1] >= 0.0)
            & (points[:, 1] <= height)
        )


def hartley_normaliser(points: Array) -> Array:
    """3x3 similarity moving the centroid of (N, 2) points to the origin, mean distance sqrt(2).

    Hartley & Zisserman 4.4.4: every linear solve runs in these coordinates.
    """
    centroid = np.add.reduce(points, axis=0) / len(points)
    offsets = points - centroid
    spread = float(np.add.reduce(np.hypot(offsets[:, 0], offsets[:, 1]))) / len(points)
    scale = math.sqrt(2.0) / spread if spread > 0 else 1.0
    cx, cy = centroid.tolist()
    return np.array([[scale, 0.0, -scale * cx], [0.0, scale, -scale * cy], [0.0, 0.0, 1.0]])


def transform(matrix: Array, points: Array) -> Array:
    """Apply a 3x3 homography to (N, 3) homogeneous points (row vectors)."""
    return points @ matrix.T


def orthogonal_complement(vector: Array) -> Array:
    """(3, 2) orthonormal basis of the plane orthogonal to a (3,) vector."""
    basis, _, _ = linalg.svd(vector.reshape(3, 1))
    return basis[:, 1:]


def skew(vector: Array) -> Array:
    """The cross-product matrix [v]x, so that skew(a) @ b == cross(a, b)."""
    x, y, z = vector
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def canonical(vector: ArrayLike) -> Array:
    """Unit norm, sign fixed (w > 0, or the largest entry positive) so results compare."""
    x, y, w = (float(v) for v in np.ravel(vector))
    pivot = w if w != 0 else max((x, y), key=abs)
    scale = math.copysign(1.0 / math.sqrt(x * x + y * y + w * w), pivot)
    return np.array((x * scale, y * scale, w * scale))


def canonical_matrix(matrix: Array) -> Array:
    """Unit Frobenius norm with the largest-magnitude entry positive."""
    matrix = matrix / linalg.norm(matrix)
    return matrix if matrix.flat[np.argmax(np.abs(matrix))] > 0 else -matrix


def left_epipole(fundamental: Array) -> Array:
    """(3,) unit ``e2`` with ``F^T e2 = 0`` (the epipole in photo 2)."""
    u, _, _ = linalg.svd(fundamental)
    return u[:, 2]


def right_epipole(fundamental: Array) -> Array:
    """(3,) unit ``e1`` with ``F e1 = 0`` (the epipole in photo 1)."""
    return linalg.null_vector(fundamental)
