"""The Cramér-Rao bound of friend 1's position in photo 2: the best any unbiased estimator
can do from a scene's taps, and a reference maximum-likelihood fit that reaches it.

The tap model is the solver's: every tap (each landmark in both photos, the friends' marks)
is the true projection plus Gaussian noise of its own sigma. The unknowns are the relative
pose of the two phones (rotation 3, direction between them 2; the distance is not
observable and fixed), each camera's intrinsics and the landmarks' 3-D points (nuisance
parameters, 3 each). A phone camera has one intrinsic, its log focal length, with the
solver's prior as information (``log_sigma``; the principal point is taken as known); a
camera with no model (the paper's projective route) has five (log focal, principal point,
log aspect, skew) and no prior, so its Fisher information is singular along the projective
ambiguity, which leaves friend 1's pixel alone: the bound is taken with a pseudo-inverse.

The bound is ``G I^+ G^T`` with ``I = J^T W J`` (+ the priors) the Fisher information, J
the Jacobian of every tap's expected position (central differences) and G that of friend
1's pixel (Kay, *Fundamentals of Statistical Signal Processing* I, 3.8; Hartley &
Zisserman 5.2). The reference fit minimises the same whitened residuals over the same
unknowns, started at the truth (:func:`reference_fit`); at small tap noise its spread over
fresh taps is the bound (checked in ``tests/solver/test_bound.py``).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import cv2
import numpy as np

from shared_solver.estimation.least_squares import levenberg_marquardt
from shared_solver.estimation.uncertainty import CHI2_2D
from shared_solver.projective import Array, skew
from testbed.scenes import Scene

# What a route assumes of one camera: a phone (log focal with a prior of that log sigma) or
# nothing (the projective model: five free intrinsics).
CameraPrior = float | None
Marks = Literal["e1", "both", "line", "none"]

_STEP = 1e-6
# A gradient this far (relatively) outside the information's range is not determined.
_IDENTIFIABLE = 1e-4
# central differences, relative to each unknown's scale
# Fixed standard normal draws for the median of a 2-D Gaussian's length: deterministic.
_DRAWS = np.random.default_rng(1903).normal(size=(20000, 2))


@dataclass(frozen=True)
class Bound:
    """The Cramér-Rao bound of friend 1's pixel in photo 2.

    Attributes:
        covariance: (2, 2) px^2, the smallest covariance an unbiased estimator can have.
    """

    covariance: Array

    @property
    def rms(self) -> float:
        """Root mean square error at the bound, px: sqrt(trace)."""
        return math.sqrt(float(np.trace(self.covariance)))

    @property
    def median(self) -> float:
        """Median error at the bound, px (the median length of a draw of the Gaussian)."""
        if not np.all(np.isfinite(self.covariance)):
            return math.inf
        values = np.linalg.eigvalsh(self.covariance).clip(min=0.0)
        return float(np.median(np.sqrt((_DRAWS**2) @ values)))

    @property
    def area(self) -> float:
        """Area of the bound's 95 % ellipse, px^2."""
        return math.pi * CHI2_2D * math.sqrt(max(float(np.linalg.det(self.covariance)), 0.0))


@dataclass(frozen=True)
class _Model:
    """The unknowns around the truth of one scene and what each tap measures of them."""

    scene: Scene
    count: int  # landmarks used: the scene's first ``count``
    priors: tuple[CameraPrior, CameraPrior]
    marks: Marks
    line1: Array | None  # (2,) unit normal of the drawn line through friend 2, photo 1

    @property
    def intrinsic_counts(self) -> tuple[int, int]:
        return tuple(1 if prior is not None else 5 for prior in self.priors)  # type: ignore[return-value]

    @property
    def size(self) -> int:
        return 5 + sum(self.intrinsic_counts) + 3 * self.count

    def truth(self) -> Array:
        """The unknowns at the truth: zero steps of pose and intrinsics, then each point as
        (x / z, y / z, d / z) in frame 1, d the distance between the phones: every unknown
        of order one (Levenberg-Marquardt crawled with points in metres)."""
        c1 = self.scene.camera1
        points = self.scene.points[: self.count] @ c1.rotation.T + c1.translation  # frame 1
        inverse = np.column_stack([points[:, :2], np.full(len(points), self.distance)])
        inverse /= points[:, 2:]
        return np.concatenate([np.zeros(5 + sum(self.intrinsic_counts)), inverse.ravel()])

    @functools.cached_property
    def distance(self) -> float:
        return float(np.linalg.norm(self.scene.camera2.centre - self.scene.camera1.centre))

    def points(self, theta: Array) -> Array:
        """(N, 3) the landmarks in frame 1 from the unknowns."""
        inverse = theta[-3 * self.count :].reshape(-1, 3)
        return np.column_stack([inverse[:, :2], np.ones(len(inverse))]) * (
            self.distance / inverse[:, 2:]
        )

    @functools.cached_property
    def pose(self) -> tuple[Array, Array, Array]:
        """The true pose in frame 1: R, camera 2's centre, a (3, 2) tangent basis of its
        direction."""
        c1, c2 = self.scene.camera1, self.scene.camera2
        centre2 = c1.rotation @ (c2.centre - c1.centre)
        tangent = np.linalg.svd(centre2[None])[2][1:].T
        return c2.rotation @ c1.rotation.T, centre2, tangent

    def cameras(self, theta: Array) -> tuple[Array, Array, Array, Array]:
        """(K1, K2, R, c2) at the unknowns ``theta``: frame 2 is ``R (X - c2)``."""
        rotation0, centre2, tangent = self.pose
        distance = float(np.linalg.norm(centre2))
        turn, _ = cv2.Rodrigues(theta[:3])
        b = centre2 / distance + tangent @ theta[3:5]
        b = distance * b / np.linalg.norm(b)
        n1, n2 = self.intrinsic_counts
        k1 = _intrinsics(self.scene.camera1.intrinsics, theta[5 : 5 + n1])
        k2 = _intrinsics(self.scene.camera2.intrinsics, theta[5 + n1 : 5 + n1 + n2])
        return k1, k2, turn @ rotation0, b

    def predicted(self, theta: Array) -> Array:
        """(M,) every tap's expected value: landmarks in photo 1 then 2, then the marks."""
        k1, k2, rotation, b = self.cameras(theta)
        points = self.points(theta)
        values = [_project(k1, points), _project(k2, (points - b) @ rotation.T)]
        friend2 = _project(k1, b[None])[0]
        if self.marks in ("e1", "both"):
            values.append(friend2)
        if self.marks == "line":
            assert self.line1 is not None
            values.append(np.array([self.line1 @ friend2]))
        if self.marks == "both":
            values.append(_project(k2, (-rotation @ b)[None])[0])
        return np.concatenate([v.ravel() for v in values])

    def friend1(self, theta: Array) -> Array:
        """(2,) friend 1's pixel in photo 2."""
        _, k2, rotation, b = self.cameras(theta)
        return _project(k2, (-rotation @ b)[None])[0]

    def jacobian(self, function: Callable[[Array], Array], theta: Array) -> Array:
        steps = np.eye(self.size) * _STEP
        columns = [(function(theta + d) - function(theta - d)) / (2 * _STEP) for d in steps]
        return np.column_stack(columns)


def _intrinsics(true: Array, steps: Array) -> Array:
    """K after steps of (log focal[, cx, cy, log aspect, skew]) from the true K."""
    k = true.copy()
    k[0, 0] *= math.exp(steps[0])
    k[1, 1] *= math.exp(steps[0])
    if len(steps) == 5:
        k[0, 2] += steps[1]
        k[1, 2] += steps[2]
        k[1, 1] *= math.exp(steps[3])
        k[0, 1] += steps[4] * true[0, 0]
    return k


def _project(k: Array, points: Array) -> Array:
    image = points @ k.T
    return image[:, :2] / image[:, 2:]


def _model(
    scene: Scene,
    landmarks: int,
    priors: tuple[CameraPrior, CameraPrior],
    marks: Marks,
    line_angle: float,
) -> _Model:
    normal = np.array([math.cos(line_angle), math.sin(line_angle)])
    return _Model(scene, landmarks, priors, marks, normal if marks == "line" else None)


def _weights(
    count: int,
    marks: Marks,
    sigma: float | tuple[Array, Array],
    mark_sigma: float | Array | None,
) -> Array:
    """(M,) inverse variances of the taps of ``count`` landmarks and the ``marks``, in
    :meth:`_Model.predicted`'s order.

    ``sigma``: one sigma for every landmark tap, or (N,) sigmas per landmark in photo 1 and
    in photo 2; ``mark_sigma``: one sigma for the marks, or one per mark, or None (as the
    landmarks, which must then have one sigma)."""
    if isinstance(sigma, tuple):
        per_photo = [np.repeat(np.asarray(s, dtype=np.float64)[:count], 2) for s in sigma]
        landmark = 1.0 / np.concatenate(per_photo) ** 2
    else:
        landmark = np.full(4 * count, 1.0 / sigma**2)
    if mark_sigma is None:
        assert not isinstance(sigma, tuple), "per-tap sigmas need the marks' sigma"
        mark_sigma = sigma
    each = np.broadcast_to(np.asarray(mark_sigma, dtype=np.float64), (_MARKS[marks],))
    per_mark = 1 if marks == "line" else 2
    return np.concatenate([landmark, np.repeat(1.0 / each**2, per_mark)])


_MARKS = {"e1": 1, "both": 2, "line": 1, "none": 0}  # marks made


class SceneBounds:
    """The bound's ingredients for one scene, computed once: the Jacobians of every tap and
    of friend 1's pixel at the truth. A bound for the scene's first n landmarks, any tap
    noise and any priors of the same kind is then a slice and an inverse (a benchmark asks
    for many on each scene).

    Args:
        scene: the truth.
        modelled: the cameras have a model (one intrinsic each: a phone or EXIF prior);
            False: the projective model (five free intrinsics each, no prior).
        marks, line_angle: as for :func:`cramer_rao`.
        landmarks: the most landmarks a bound will use (default: all the scene's).
    """

    def __init__(
        self,
        scene: Scene,
        *,
        modelled: bool,
        marks: Marks = "e1",
        line_angle: float = 0.0,
        landmarks: int | None = None,
    ) -> None:
        count = len(scene.points) if landmarks is None else landmarks
        kind: tuple[CameraPrior, CameraPrior] = (1.0, 1.0) if modelled else (None, None)
        self.model = _model(scene, count, kind, marks, line_angle)
        theta = self.model.truth()
        self.jacobian = self.model.jacobian(self.model.predicted, theta)
        self.g = self.model.jacobian(self.model.friend1, theta)

    def bound(
        self,
        landmarks: int,
        sigma: float | tuple[Array, Array],
        priors: tuple[CameraPrior, CameraPrior],
        mark_sigma: float | Array | None = None,
        gravity_sigma_deg: float | None = None,
    ) -> Bound:
        """The bound from the first ``landmarks`` (arguments as :func:`cramer_rao`); with
        ``gravity_sigma_deg``, each phone also read down (world y) with that sigma per axis
        (:meth:`_gravity_information`)."""
        model = self.model
        assert landmarks <= model.count
        assert all(
            (prior is None) == (count == 5)
            for prior, count in zip(priors, model.intrinsic_counts, strict=True)
        ), "priors of another kind of camera than these bounds were made for"
        total, marks = model.count, 2 * _MARKS[model.marks] - (model.marks == "line")
        rows = np.r_[0 : 2 * landmarks, 2 * total : 2 * total + 2 * landmarks]
        rows = np.r_[rows, 4 * total : 4 * total + marks]
        pose = 5 + sum(model.intrinsic_counts)
        columns = np.r_[0:pose, pose : pose + 3 * landmarks]
        jacobian = self.jacobian[np.ix_(rows, columns)]
        weights = _weights(landmarks, model.marks, sigma, mark_sigma)
        information = jacobian.T @ (jacobian * weights[:, None])
        n1, _ = model.intrinsic_counts
        for index, prior in zip((5, 5 + n1), priors, strict=True):
            if prior is not None:
                information[index, index] += 1.0 / prior**2
        g = self.g[:, columns]
        if gravity_sigma_deg is not None:
            information, g = self._gravity_information(information, g, gravity_sigma_deg)
        inverse = np.linalg.pinv(information, hermitian=True)
        # Friend 1's pixel is determined only if its gradient lies in the information's
        # range (with four landmarks and no camera model it is not: a curve, no point).
        unseen = g - g @ inverse @ information
        if np.abs(unseen).max() > _IDENTIFIABLE * np.abs(g).max():
            return Bound(np.full((2, 2), np.inf))
        return Bound(g @ inverse @ g.T)

    def _gravity_information(
        self, information: Array, g: Array, sigma_deg: float
    ) -> tuple[Array, Array]:
        """The information and friend 1's gradient with two more unknowns, the true down in
        frame 1 (two steps across it, a nuisance), and two readings of it: photo 1's reads it
        directly, photo 2's after the rotation; each across itself, ``sigma_deg`` per axis.

        With ``R = exp([t]x) R0`` (the pose's first three unknowns ``t``), the reading in
        photo 2 moves by ``-T2^T [v2]x`` per step of ``t`` and ``T2^T R0 T1`` per step of
        down, for tangent bases T1 and T2 across the true down v1 and v2 = R0 v1."""
        rotation0 = self.model.pose[0]
        down1 = self.model.scene.camera1.down
        down2 = rotation0 @ down1
        across1 = np.linalg.svd(down1[None])[2][1:].T  # (3, 2)
        across2 = np.linalg.svd(down2[None])[2][1:].T
        size = information.shape[0]
        jacobian = np.zeros((4, size + 2))
        jacobian[0:2, size:] = np.eye(2)
        jacobian[2:4, 0:3] = -across2.T @ skew(down2)
        jacobian[2:4, size:] = across2.T @ rotation0 @ across1
        grown = np.zeros((size + 2, size + 2))
        grown[:size, :size] = information
        grown += jacobian.T @ jacobian / math.radians(sigma_deg) ** 2
        return grown, np.hstack([g, np.zeros((2, 2))])


def cramer_rao(
    scene: Scene,
    *,
    landmarks: int,
    sigma: float | tuple[Array, Array],
    priors: tuple[CameraPrior, CameraPrior],
    marks: Marks = "e1",
    mark_sigma: float | Array | None = None,
    line_angle: float = 0.0,
    gravity_sigma_deg: float | None = None,
) -> Bound:
    """The bound of friend 1's pixel in photo 2 from the scene's first ``landmarks``.

    Args:
        scene: the truth (its first ``landmarks`` points are the landmarks tapped).
        landmarks: how many landmarks both people tap.
        sigma: every landmark tap's standard deviation, px per axis; or (N,) sigmas of
            each landmark's tap in photo 1 and in photo 2.
        priors: each camera's log-focal prior sigma (0.5 a phone, 0.02 EXIF), or None for
            no camera model (five free intrinsics, no prior); both of one kind.
        marks: which friends are marked: friend 2 in photo 1 (``e1``), both, a line through
            friend 2 in photo 1 (at ``line_angle``, its normal's angle, radians), none.
        mark_sigma: a mark's standard deviation, px, or one per mark (friend 2's, then
            friend 1's); default ``sigma``.
        gravity_sigma_deg: both phones read down at the shutter with this sigma per axis
            (degrees); None: no reading.
    """
    bounds = SceneBounds(
        scene,
        modelled=priors[0] is not None,
        marks=marks,
        line_angle=line_angle,
        landmarks=landmarks,
    )
    return bounds.bound(landmarks, sigma, priors, mark_sigma, gravity_sigma_deg)


def reference_fit(
    scene: Scene,
    taps: Array,
    *,
    landmarks: int,
    sigma: float,
    priors: tuple[CameraPrior, CameraPrior],
    marks: Marks = "e1",
    prior_offsets: Array | None = None,
) -> Array:
    """Friend 1's pixel (2,) by maximum likelihood over every unknown (bundle adjustment with
    the focal priors), started at the truth.

    Args:
        taps: (M,) the taps in :func:`tap_vector`'s order.
        prior_offsets: (2,) each prior's mean minus the true log focal (default 0).
    """
    model = _model(scene, landmarks, priors, marks, 0.0)
    whiten = np.sqrt(_weights(model.count, marks, sigma, None))
    offsets = np.zeros(2) if prior_offsets is None else prior_offsets
    n1, _ = model.intrinsic_counts
    prior_rows = [
        (index, prior, offset)
        for index, prior, offset in zip((5, 5 + n1), priors, offsets, strict=True)
        if prior is not None
    ]

    def whole(values: Array) -> Array:
        r = whiten * (model.predicted(values) - taps)
        priors_r = [(values[i] - offset) / prior for i, prior, offset in prior_rows]
        return np.concatenate([r, np.array(priors_r)])

    def residuals(theta: Array) -> tuple[Array, Array]:
        return whole(theta), model.jacobian(whole, theta)

    theta, _, _ = levenberg_marquardt(
        residuals, model.truth(), max_iterations=30, gain_tolerance=(1e-6, 1e-10)
    )
    return model.friend1(theta)


def tap_vector(scene: Scene, landmarks: int, taps1: Array, taps2: Array, e1: Array) -> Array:
    """(4N + 2,) taps in the reference fit's order: landmarks in photo 1, photo 2, then e1."""
    return np.concatenate([taps1[:landmarks].ravel(), taps2[:landmarks].ravel(), e1])
