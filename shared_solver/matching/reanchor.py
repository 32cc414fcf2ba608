"""Re-anchoring a live view: how a phone has turned since its photo, from one camera frame.

A phone that stands where it took its photo and turns sees the scene through a pure
rotation: a pixel ``x`` of the photo appears in the frame at ``K_f R K_p^-1 x`` (Hartley &
Zisserman 8.4.2, a homography of a rotating camera). So a frame matched to the photo gives
the rotation ``R`` (photo's camera frame to the frame's), which resets whatever the phone's
gyroscope has drifted since the shutter, and the frame's focal length ``f_f``, which the
video stream's crop and zoom set (measured, not assumed).

Steps (:func:`reanchor`): SIFT features in both (scale-invariant, and steady under the
exposure changes of a live view), Lowe's ratio test, a homography by MAGSAC (OpenCV's
``USAC_MAGSAC``), then the rotation read from it: ``A = K_f' R`` with ``A = H K_p``, whose
columns are orthogonal once divided by ``f_f`` (:func:`frame_focal`), the nearest rotation
to ``diag(1/f_f, 1/f_f, 1) A``, refined over the inliers' rays (Kabsch). A match is
refused (``FRAME_NOT_MATCHED``) unless enough inliers, spread over the frame, fit the
rotation itself, not just the homography: a wrong match must not move the marker. A frame
refused at its size is tried once more at half of it (a turning phone's motion blur halves
with it), under the same rules.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from ..errors import Reason
from ..projective import Array
from ..refusal import SolverError
from .polar import Image

# Features are found on images of at most this long side (a live frame is sent at about
# this size; the stored photo is scaled down to it): SIFT on a 12 MP photo takes seconds.
_WORKING_SIDE = 960
_FEATURES = 3000
# SIFT's contrast threshold, half OpenCV's default (0.04): a dim frame (a dark hall, the
# exposure still settling) kept 3-4 times the inliers (82 -> 305 on a rendered hall at x0.4).
_CONTRAST = 0.02
# Lowe's ratio test (Lowe 2004, 7.1): a match is kept when its nearest neighbour is clearly
# nearer than the second.
_RATIO = 0.8
# The homography's inlier threshold, px in the frame.
_THRESHOLD_PX = 3.0
# A frame is matched when at least this many inliers fit the rotation, they are at least
# this share of the homography's, and their hull covers this share of the frame.
_MIN_INLIERS = 40
_MIN_SHARE = 0.8
_MIN_COVER = 0.05
# A frame focal length this far from the one expected (a factor) is no phone's video.
_FOCAL_FACTOR = 4.0
# A frame refused at its own size is tried once more at this scale, the photo with it: a
# turning phone's motion blur shrinks with the pixels (15 px at 960 px is 7.5 at 480), and
# SIFT finds its corners again. Only refused frames pay for it.
_COARSE = 0.5


@dataclass(frozen=True)
class Reanchored:
    """How the phone has turned since its photo, from one matched frame.

    Attributes:
        rotation: (3, 3) R taking a direction in the photo's camera frame (x right, y
            down, z out of the lens) to the frame's.
        frame_focal_px: the frame's focal length, px of the frame as sent.
        inliers: features that fit the rotation.
        residual_px: their median distance from where the rotation puts them, frame px.
    """

    rotation: Array
    frame_focal_px: float
    inliers: int
    residual_px: float

    @property
    def degrees(self) -> float:
        """How far the phone has turned, degrees."""
        cosine = (float(np.trace(self.rotation)) - 1.0) / 2.0
        return math.degrees(math.acos(min(1.0, max(-1.0, cosine))))


def reanchor(
    photo: Image,
    frame: Image,
    photo_focal_px: float,
    *,
    frame_focal_px: float | None = None,
) -> Reanchored:
    """The rotation from ``photo``'s camera to ``frame``'s, both taken from one place.

    Args:
        photo: (H, W) or (H, W, 3) uint8, the stored photo.
        frame: (h, w) or (h, w, 3) uint8, a frame of the live view.
        photo_focal_px: the photo's focal length, px of the photo (the answer's
            ``cameras[i].focal_px``); principal points are the images' centres.
        frame_focal_px: the frame's, when known; None: measured from the match.

    Raises:
        SolverError: ``FRAME_NOT_MATCHED`` when no rotation explains enough of the frame,
            at its size or at half of it.
    """
    seen = _grey(frame)
    try:
        return _reanchored(photo, seen, photo_focal_px, frame_focal_px, _WORKING_SIDE)
    except SolverError:
        size = (round(seen.shape[1] * _COARSE), round(seen.shape[0] * _COARSE))
        coarse = np.asarray(cv2.resize(seen, size, interpolation=cv2.INTER_AREA), np.uint8)
        known = None if frame_focal_px is None else frame_focal_px * _COARSE
        found = _reanchored(photo, coarse, photo_focal_px, known, _WORKING_SIDE * _COARSE)
    # In pixels of the frame as sent.
    return Reanchored(
        rotation=found.rotation,
        frame_focal_px=found.frame_focal_px / _COARSE,
        inliers=found.inliers,
        residual_px=found.residual_px / _COARSE,
    )


def _reanchored(
    photo: Image, seen: Image, photo_focal_px: float, frame_focal_px: float | None, side: float
) -> Reanchored:
    """:func:`reanchor` of the grey frame ``seen`` as it is, the photo scaled to at most
    ``side`` px."""
    small, scale = _working(photo, side)
    photo_points, frame_points = _matches(small, seen)
    if len(photo_points) < _MIN_INLIERS:
        raise SolverError(Reason.FRAME_NOT_MATCHED)
    found, mask = cv2.findHomography(
        photo_points, frame_points, cv2.USAC_MAGSAC, _THRESHOLD_PX, maxIters=5000
    )
    if found is None or int(mask.sum()) < _MIN_INLIERS:
        raise SolverError(Reason.FRAME_NOT_MATCHED)
    homography: Array = np.asarray(found, dtype=np.float64)
    kept = mask.ravel().astype(bool)
    k_photo = _intrinsics(photo_focal_px * scale, small.shape)
    measured = frame_focal(homography, k_photo, _centre(seen.shape))
    focal = measured if frame_focal_px is None else frame_focal_px
    expected = frame_focal_px or photo_focal_px * max(seen.shape[:2]) / max(photo.shape[:2])
    if not (focal > 0 and 1.0 / _FOCAL_FACTOR <= focal / expected <= _FOCAL_FACTOR):
        raise SolverError(Reason.FRAME_NOT_MATCHED)
    k_frame = _intrinsics(focal, seen.shape)
    rotation = _nearest_rotation(np.linalg.inv(k_frame) @ homography @ k_photo)
    rotation = _kabsch(photo_points[kept], frame_points[kept], k_photo, k_frame, rotation)
    residuals = _residuals(photo_points, frame_points, k_photo, k_frame, rotation)
    fits = residuals <= _THRESHOLD_PX
    if (
        int(fits.sum()) < _MIN_INLIERS
        or fits.sum() < _MIN_SHARE * kept.sum()
        or _cover(frame_points[fits], seen.shape) < _MIN_COVER
    ):
        raise SolverError(Reason.FRAME_NOT_MATCHED)
    return Reanchored(
        rotation=rotation,
        frame_focal_px=float(focal),
        inliers=int(fits.sum()),
        residual_px=float(np.median(residuals[fits])),
    )


def frame_focal(homography: Array, photo_intrinsics: Array, frame_centre: Array) -> float:
    """The frame's focal length (px) that makes a rotation of ``homography`` (3, 3), photo
    pixels to frame pixels: with ``A = T^-1 H K_p`` (``T`` the frame's centre shift) and
    ``D = diag(1/f, 1/f, 1)``, ``D A`` is a rotation times a scale, so
    ``A^T diag(u, u, 1) A = s^2 I`` with ``u = 1/f^2``: linear in ``(u, s^2)``, solved by
    least squares over its six distinct entries. NaN when no positive ``u`` fits."""
    shift = np.array([[1.0, 0.0, -frame_centre[0]], [0.0, 1.0, -frame_centre[1]], [0.0, 0.0, 1.0]])
    a = shift @ homography @ photo_intrinsics
    rows = np.triu_indices(3)
    planar = (np.outer(a[0], a[0]) + np.outer(a[1], a[1]))[rows]
    depth = np.outer(a[2], a[2])[rows]
    identity = np.eye(3)[rows]
    # u planar + depth = s^2 identity: unknowns (u, s^2).
    design = np.column_stack([planar, -identity])
    (u, _), *_ = np.linalg.lstsq(design, -depth, rcond=None)
    return 1.0 / math.sqrt(u) if u > 0 else math.nan


def _working(photo: Image, side: float) -> tuple[Image, float]:
    """The photo in grey, scaled down to at most ``side`` px, and the scale."""
    grey = _grey(photo)
    scale = min(1.0, side / max(grey.shape[:2]))
    if scale == 1.0:
        return grey, scale
    size = (round(grey.shape[1] * scale), round(grey.shape[0] * scale))
    return np.asarray(cv2.resize(grey, size, interpolation=cv2.INTER_AREA), np.uint8), scale


def _grey(image: Image) -> Image:
    if image.ndim == 3:
        return np.asarray(cv2.cvtColor(image, cv2.COLOR_BGR2GRAY))
    return image


def _matches(photo: Image, frame: Image) -> tuple[Array, Array]:
    """(M, 2) float32 matched pixels in the photo and in the frame."""
    sift = cv2.SIFT_create(  # type: ignore[attr-defined]
        nfeatures=_FEATURES, contrastThreshold=_CONTRAST
    )
    keys1, described1 = sift.detectAndCompute(photo, None)
    keys2, described2 = sift.detectAndCompute(frame, None)
    if described1 is None or described2 is None or len(keys1) < 2 or len(keys2) < 2:
        return np.zeros((0, 2), np.float32), np.zeros((0, 2), np.float32)
    pairs = cv2.BFMatcher(cv2.NORM_L2).knnMatch(described1, described2, k=2)
    good = [m for m, n in (p for p in pairs if len(p) == 2) if m.distance < _RATIO * n.distance]
    first = np.array([keys1[m.queryIdx].pt for m in good], np.float32).reshape(-1, 2)
    second = np.array([keys2[m.trainIdx].pt for m in good], np.float32).reshape(-1, 2)
    return first, second


def _centre(shape: tuple[int, ...]) -> Array:
    return np.array([shape[1] / 2.0, shape[0] / 2.0])


def _intrinsics(focal: float, shape: tuple[int, ...]) -> Array:
    cx, cy = _centre(shape)
    return np.array([[focal, 0.0, cx], [0.0, focal, cy], [0.0, 0.0, 1.0]])


def _nearest_rotation(matrix: Array) -> Array:
    """The rotation nearest ``matrix`` (3, 3) in the Frobenius norm (SVD, determinant +1)."""
    u, _, vt = np.linalg.svd(matrix)
    fix = np.diag([1.0, 1.0, float(np.sign(np.linalg.det(u @ vt)))])
    result: Array = u @ fix @ vt
    return result


def _rays(points: Array, intrinsics: Array) -> Array:
    """(M, 3) unit rays of (M, 2) pixels."""
    homogeneous = np.column_stack([points, np.ones(len(points))]) @ np.linalg.inv(intrinsics).T
    result: Array = homogeneous / np.linalg.norm(homogeneous, axis=1, keepdims=True)
    return result


def _kabsch(
    photo_points: Array, frame_points: Array, k_photo: Array, k_frame: Array, start: Array
) -> Array:
    """The rotation that best aligns the inliers' rays (Kabsch), or ``start`` when they
    cannot fix one."""
    if len(photo_points) < 3:
        return start
    cross = _rays(frame_points, k_frame).T @ _rays(photo_points, k_photo)
    return _nearest_rotation(cross)


def _residuals(
    photo_points: Array, frame_points: Array, k_photo: Array, k_frame: Array, rotation: Array
) -> Array:
    """(M,) px in the frame between each match and where the rotation puts its photo
    pixel (infinite behind the frame's camera)."""
    carried = _rays(photo_points, k_photo) @ rotation.T @ k_frame.T
    with np.errstate(divide="ignore", invalid="ignore"):
        projected = carried[:, :2] / carried[:, 2:]
        distance = np.hypot(*(projected - frame_points).T)
    result: Array = np.where(carried[:, 2] > 0, distance, np.inf)
    return result


def _cover(points: Array, shape: tuple[int, ...]) -> float:
    """The share of the frame inside the points' convex hull."""
    if len(points) < 3:
        return 0.0
    hull = cv2.convexHull(points.astype(np.float32))
    return float(cv2.contourArea(hull)) / float(shape[0] * shape[1])
