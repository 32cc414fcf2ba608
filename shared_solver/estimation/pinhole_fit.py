"""Maximum a posteriori two-view geometry of two pinhole cameras (square pixels, centred).

The model: camera 1 (friend 1's) sees friend 2 in the direction ``b1`` (unit, frame 1);
frame 2 is ``X2 = R X1 + t`` with ``t`` along ``-R b1``; each camera has its own focal
length ``f_k`` (px) and its principal point at the photo's centre ``c_k``. Then

    F = K2^-T R [b1]x K1^-1,   e1 ~ K1 b1,   e2 ~ -K2 R b1   (oriented: w > 0 in front),

and a landmark with rays ``p^ = K1^-1 p``, ``q^ = K2^-1 q`` fits when ``q^ . R (b1 x p^) = 0``
(Hartley & Zisserman 9.6). Seven parameters: the rotation (3), friend 2's direction (2)
and the two log focal lengths (2), the last with the cameras' priors (:mod:`.camera`).

Friend 2's direction is kept as a camera of a fixed reference focal length would see it,
``u``, and ``b1 ~ diag(r, r, 1) u`` with ``r = f_reference / f1``: friend 2's pixel then
does not move when the focal length does, and a step in ``f1`` does not fight
friend 2's tap.

Every tap counts with its own covariance: a landmark by its Sampson distance (H & Z 11.4.3)
whitened by the covariances of its two taps, the friends' marks by their offset from the
model's epipoles. The minimum of the sum of squares is the maximum a posteriori estimate to
first order, and the inverse of ``J^T J`` its covariance (the Laplace approximation).

Everything runs on a batch of K poses and K sets of taps at once: K = 1 for a fit, several
for scoring the exact solvers' poses (:mod:`.pinhole_starts`), and K sets of re-made taps
for the bootstrap (:mod:`.bootstrap`), so all use the same code.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import cv2
import numpy as np

from .. import linalg
from ..projective import Array
from .camera import FocalPrior
from .least_squares import levenberg_marquardt
from .taps import Taps, whitener

# Parameters: rotation step (3), friend 2's direction step in its tangent plane (2), log focal
# steps (2).
PARAMETERS = 7
_ROTATION, _BASELINE, _FOCAL1, _FOCAL2 = slice(0, 3), slice(3, 5), 5, 6
# The cost is a chi-square: stop when a step gains less than 1e-6 of it (the estimate then
# moves by about 1e-3 of its own sigma), or 1e-16 on exact taps (1e-8 sigma).
_GAIN_TOLERANCE = (1e-5, 1e-16)
# A fit whose focal lengths end this many prior sigmas away ran off (e^5 = 150 times).
_FOCAL_RANGE_SIGMAS = 10.0
# Logarithms beyond this overflow (or underflow to zero) in math.exp: a fit that runs off to
# such focal lengths gets non-finite residuals, and its step is rejected.
_LOG_RANGE = 700.0
# Below this |w| of the direction friend 1 is seen in, they are at infinity in photo 2.
_AT_INFINITY = 1e-12


@dataclass(frozen=True)
class Poses:
    """K relative poses with focal lengths: points of the model's parameter space.

    Attributes:
        rotation: (K, 3, 3) R from frame 1 to frame 2.
        friend2: (K, 3) unit u: friend 2's direction as seen with photo 1's reference focal
            length (module docstring).
        log_focals: (K, 2) ln(f1), ln(f2), f in px.
        reference: ln of photo 1's reference focal length, px.
    """

    rotation: Array
    friend2: Array
    log_focals: Array
    reference: float

    @classmethod
    def one(cls, rotation: Array, baseline: Array, log_focals: Array) -> Poses:
        """A batch of one: R (3, 3), b1 (3,) (any length), (ln f1, ln f2); the reference is
        this f1, so friend 2's direction is b1 itself."""
        baseline = np.asarray(baseline, dtype=np.float64)
        log_focals = np.asarray(log_focals, dtype=np.float64)
        return cls(
            np.asarray(rotation, dtype=np.float64)[None],
            (baseline / linalg.norm(baseline))[None],
            log_focals[None],
            float(log_focals[0]),
        )

    def __len__(self) -> int:
        return len(self.rotation)

    def moved(self, steps: Array) -> Poses:
        """A batch of one after a tangent step (1, 7): ``exp([w]x) R``, friend 2, log focals;
        in plain floats and OpenCV (this runs at every step of every fit)."""
        step = steps[0]
        x, y, z = self.friend2[0].tolist()
        (fx, sx), (fy, sy), (fz, sz) = _tangent(x, y, z)
        a, b = step[3:5].tolist()
        x, y, z = x + fx * a + sx * b, y + fy * a + sy * b, z + fz * a + sz * b
        norm = math.sqrt(x * x + y * y + z * z)
        turn, _ = cv2.Rodrigues(step[:3])
        return Poses(
            (turn @ self.rotation[0])[None],
            np.array([[x / norm, y / norm, z / norm]]),
            self.log_focals + step[5:7],
            self.reference,
        )

    def after_steps(self, steps: Array) -> Poses:
        """K poses: this one (a batch of one) after each of K tangent steps (K, 7), as
        :meth:`moved` does one (Rodrigues' formula on the rotations, in a batch)."""
        tangent = np.array(_tangent(*self.friend2[0].tolist()))
        friend2 = self.friend2[0] + steps[:, _BASELINE] @ tangent.T
        friend2 /= np.sqrt(np.einsum("ki,ki->k", friend2, friend2))[:, None]
        w = steps[:, _ROTATION]
        angle = np.sqrt(np.einsum("ki,ki->k", w, w))
        small = angle < 1e-8
        safe = np.where(small, 1.0, angle)
        first = np.where(small, 1.0, np.sin(safe) / safe)[:, None, None]
        second = np.where(small, 0.5, (1.0 - np.cos(safe)) / (safe * safe))[:, None, None]
        cross = _skews(w)
        turn = np.eye(3) + first * cross + second * (cross @ cross)
        return Poses(
            turn @ self.rotation[0],
            friend2,
            self.log_focals[0] + steps[:, 5:7],
            self.reference,
        )

    @functools.cached_property
    def ratio(self) -> Array:
        """(K,) f_reference / f1."""
        return np.exp(self.reference - self.log_focals[:, 0])

    @functools.cached_property
    def baseline(self) -> Array:
        """(K, 3) b1 up to a positive scale: from camera 1 towards camera 2, frame 1."""
        baseline = self.friend2.copy()
        baseline[:, :2] *= self.ratio[:, None]
        return baseline

    def member(self, k: int) -> Poses:
        """The k-th pose as a batch of one."""
        return Poses(
            self.rotation[k : k + 1],
            self.friend2[k : k + 1],
            self.log_focals[k : k + 1],
            self.reference,
        )


@dataclass(frozen=True)
class PinholeFit:
    """A fitted pinhole geometry, its cost and its covariance.

    Attributes:
        pose: the estimate (a batch of one).
        centres: (2, 2) principal points of photo 1 and 2, px.
        cost: sum of squared whitened residuals, priors included (a chi-square).
        dof: residuals minus parameters.
        covariance: (7, 7) of the tangent parameters.
        distances: (N,) whitened Sampson distance of each landmark (in its own sigmas).
        jacobian: (M, 7) of all whitened residuals at the estimate.
        prior_offsets: (2,) each log focal length's distance from its prior, in sigmas.
    """

    pose: Poses
    centres: Array
    cost: float
    dof: int
    covariance: Array
    distances: Array
    jacobian: Array
    prior_offsets: Array

    @property
    def usable(self) -> bool:
        """Whether the fit is a number throughout, with focal lengths within ten prior
        sigmas: a start far from any geometry can run off to absurd ones."""
        return bool(
            np.isfinite(self.cost)
            and np.all(np.isfinite(self.covariance))
            and np.all(np.isfinite(self.jacobian))
            and np.all(np.isfinite(self.pose.rotation))
            and np.all(np.abs(self.distances) < np.inf)
            and np.all(np.abs(self.prior_offsets) <= _FOCAL_RANGE_SIGMAS)
        )

    @functools.cached_property
    def focals(self) -> tuple[float, float]:
        """Focal lengths of photo 1 and photo 2, px."""
        log_f1, log_f2 = self.pose.log_focals[0].tolist()
        return _exp(log_f1), _exp(log_f2)

    @functools.cached_property
    def intrinsics(self) -> tuple[Array, Array]:
        return _k(self.focals[0], self.centres[0]), _k(self.focals[1], self.centres[1])

    @functools.cached_property
    def fundamental(self) -> Array:
        """(3, 3) F in pixels, unit Frobenius norm."""
        k1, k2 = self.intrinsics
        essential = self.pose.rotation[0] @ _skews(self.pose.baseline)[0]
        f = linalg.solve(k2.T, essential) @ linalg.inv(k1)
        return f / linalg.norm(f)

    @functools.cached_property
    def epipole1(self) -> Array:
        """(3,) friend 2 in photo 1, oriented (w > 0: in front of friend 1's camera)."""
        return self.intrinsics[0] @ self.pose.baseline[0]

    @functools.cached_property
    def epipole2(self) -> Array:
        """(3,) friend 1 in photo 2, oriented (w > 0: in front of friend 2's camera)."""
        return self.intrinsics[1] @ (-self.pose.rotation[0] @ self.pose.baseline[0])

    @functools.cached_property
    def fundamental_covariance(self) -> Array:
        """(9, 9) first-order covariance of :attr:`fundamental` read row by row: F's
        derivatives along the 7 parameters, through the parameters' covariance, projected
        on the unit sphere (F is kept at unit norm, so it cannot vary along itself)."""
        tangent = np.array(_tangent(*self.pose.friend2[0].tolist()))
        (x1, y1), (x2, y2) = self.centres.tolist()
        stacked = fundamental_stack(self.pose, ((x1, y1), (x2, y2)), tangent).reshape(8, 9)
        norm = linalg.norm(stacked[0])
        unit = stacked[0] / norm
        derivatives = stacked[1:].T / norm  # (9, 7)
        jacobian = derivatives - np.outer(unit, unit @ derivatives)
        return jacobian @ self.covariance @ jacobian.T

    @functools.cached_property
    def covariance2(self) -> Array | None:
        """(2, 2) px^2 covariance of friend 1's pixel position, None if it is at infinity."""
        centre = (float(self.centres[1, 0]), float(self.centres[1, 1]))
        tangent = np.array(_tangent(*self.pose.friend2[0].tolist()))
        position, jacobian = _friend1_pixel(self.pose, centre, tangent)
        if not np.isfinite(position[0]):
            return None
        return jacobian @ self.covariance @ jacobian.T


class PinholeModel:
    """Whitened residuals and their Jacobian for K sets of taps under one pair of priors.

    Args:
        taps: the taps; their covariances are shared by the whole batch.
        priors: the focal priors of photo 1 and photo 2 (centres = principal points).
        p, q: (K, N, 2) landmark positions per batch member (default: the taps', K = 1).
        epipole1, epipole2: (K, 2) the friends' marks per member (default: the taps').
    """

    def __init__(
        self,
        taps: Taps,
        priors: tuple[FocalPrior, FocalPrior],
        *,
        p: Array | None = None,
        q: Array | None = None,
        epipole1: Array | None = None,
        epipole2: Array | None = None,
    ) -> None:
        self.taps, self.priors = taps, priors
        p = taps.p[None] if p is None else p
        q = taps.q[None] if q is None else q
        count = len(p)
        self.p_t = np.concatenate([p.transpose(0, 2, 1), np.ones((count, 1, len(taps)))], axis=1)
        self.q_t = np.concatenate([q.transpose(0, 2, 1), np.ones((count, 1, len(taps)))], axis=1)
        self.cov_p_t = taps.cov_p.transpose(1, 2, 0)  # (2, 2, N)
        self.cov_q_t = taps.cov_q.transpose(1, 2, 0)
        self.cov_t = np.zeros((4, 4, len(taps)))  # both taps' covariances, block diagonal
        self.cov_t[:2, :2], self.cov_t[2:, 2:] = self.cov_p_t, self.cov_q_t
        self.centres = np.array([priors[0].centre, priors[1].centre])
        self.centre_pixels = (priors[0].centre, priors[1].centre)
        self.prior_mean = np.array([priors[0].log_focal, priors[1].log_focal])
        self.prior_sigma = np.array([priors[0].log_sigma, priors[1].log_sigma])
        self.prior_jacobian = np.zeros((2, PARAMETERS))
        self.prior_jacobian[0, _FOCAL1], self.prior_jacobian[1, _FOCAL2] = 1.0 / self.prior_sigma
        self.friend2 = _Mark.of(taps.epipole1, taps.cov_e1, epipole1)
        self.friend1 = _Mark.of(taps.epipole2, taps.cov_e2, epipole2)
        self.line = None
        if taps.line1 is not None:
            self.line = taps.line1 / (math.hypot(taps.line1[0], taps.line1[1]) * taps.line_sigma)
        self.landmarks = len(taps)
        marks = (
            2 * (self.friend2 is not None)
            + (self.line is not None)
            + 2 * (self.friend1 is not None)
        )
        self.residual_count = self.landmarks + marks + 2  # landmarks, marks, focal priors

    def residuals(self, pose: Poses) -> tuple[Array, Array]:
        """(r (M,), J (M, 7)) at one pose: landmarks first, then the friends' marks and the
        priors."""
        r = np.empty(self.residual_count)
        jacobian = np.empty((self.residual_count, PARAMETERS))
        log_f1, log_f2 = pose.log_focals[0].tolist()
        if not max(abs(log_f1), abs(log_f2), abs(pose.reference - log_f1)) < _LOG_RANGE:
            r[:], jacobian[:] = np.nan, np.nan
            return r, jacobian
        tangent = np.array(_tangent(*pose.friend2[0].tolist()))
        row = self.landmarks
        r[:row], jacobian[:row] = _landmarks(pose, self, tangent)
        if self.friend2 is not None or self.line is not None:
            position, d_position = _friend2_pixel(pose, self.centre_pixels[0], tangent)
            if self.friend2 is not None:
                r[row : row + 2], jacobian[row : row + 2] = self.friend2.residuals(
                    position, d_position
                )
                row += 2
            if self.line is not None:
                r[row] = position @ self.line[:2] + self.line[2]
                jacobian[row] = self.line[:2] @ d_position
                row += 1
        if self.friend1 is not None:
            position, d_position = _friend1_pixel(pose, self.centre_pixels[1], tangent)
            r[row : row + 2], jacobian[row : row + 2] = self.friend1.residuals(position, d_position)
            row += 2
        r[row:] = (pose.log_focals[0] - self.prior_mean) / self.prior_sigma
        jacobian[row:] = self.prior_jacobian
        return r, jacobian

    def offsets(self, poses: Poses) -> Array:
        """(K, M) whitened residuals, without the Jacobian: K poses against one set of taps
        (scoring candidate poses), or one pose against K sets of taps (the bootstrap)."""
        count = max(len(poses), len(self.p_t))
        f = np.exp(poses.log_focals)  # (K, 2)
        inverse1 = _inverse_k(f[:, 0], self.centres[0])
        inverse2_t = _inverse_k(f[:, 1], self.centres[1]).transpose(0, 2, 1)
        fundamental = inverse2_t @ poses.rotation @ _skews(poses.baseline) @ inverse1
        lines2 = fundamental @ self.p_t  # (K, 3, N)
        lines1 = fundamental.transpose(0, 2, 1) @ self.q_t
        eps = np.einsum("kin,kin->kn", lines2, self.q_t)
        gradients = np.concatenate(
            [np.broadcast_to(lines1[:, :2], (count, 2, self.landmarks)), lines2[:, :2]], axis=1
        )  # (K, 4, N), as in _landmarks
        weighted = np.einsum("ijn,kjn->kin", self.cov_t, gradients)
        out = np.empty((count, self.residual_count))
        out[:, : self.landmarks] = eps / np.sqrt(np.einsum("kin,kin->kn", gradients, weighted))
        column = self.landmarks
        if self.friend2 is not None or self.line is not None:
            position = _friend2_positions(poses, self.centres[0])
            if self.friend2 is not None:
                out[:, column : column + 2] = (
                    position - self.friend2.position
                ) @ self.friend2.whiten.T
                column += 2
            if self.line is not None:
                out[:, column] = position @ self.line[:2] + self.line[2]
                column += 1
        if self.friend1 is not None:
            position = friend1_positions(poses, self.centres[1])
            out[:, column : column + 2] = (position - self.friend1.position) @ self.friend1.whiten.T
            column += 2
        out[:, column:] = (poses.log_focals - self.prior_mean) / self.prior_sigma
        return out


@dataclass(frozen=True)
class _Mark:
    """A friend's mark: where it was tapped (per batch member) and its whitener."""

    position: Array  # (K, 2)
    whiten: Array  # (2, 2)

    @classmethod
    def of(cls, tap: Array | None, covariance: Array | None, batch: Array | None) -> _Mark | None:
        if tap is None or covariance is None:
            return None
        return cls(tap[None] if batch is None else batch, whitener(covariance))

    def residuals(self, model: Array, jacobian: Array) -> tuple[Array, Array]:
        """Whitened offset (2,) of the model's pixel (2,) from the mark, and its Jacobian."""
        return self.whiten @ (model - self.position[0]), self.whiten @ jacobian


def fit_pinhole(model: PinholeModel, start: Poses, *, max_iterations: int = 50) -> PinholeFit:
    """Refine a pose over every tap and both focal priors.

    Args:
        model: the taps (landmarks, N >= 1, and whichever friends' marks were made, with
            covariances) and the focal priors of photo 1 and photo 2 (their centres are the
            principal points).
        start: an initial pose (a batch of one), e.g. from :mod:`..minimal.epipole_and_three`.
        max_iterations: bound for Levenberg-Marquardt.
    """

    pose, r, jacobian = levenberg_marquardt(
        model.residuals,
        start,
        retract=lambda pose, step: pose.moved(step[None]),
        max_iterations=max_iterations,
        gain_tolerance=_GAIN_TOLERANCE,
    )
    information = jacobian.T @ jacobian
    if not np.all(np.isfinite(information)):
        # Run off to where the model has no derivative (a focal length of e^-177 px, from a
        # start far from any geometry): no covariance either, so the fit is not ``usable``.
        covariance = np.full(information.shape, np.nan)
    else:
        try:
            covariance = linalg.inv(information)
        except linalg.LinAlgError:
            covariance = np.linalg.pinv(information, hermitian=True)
    return PinholeFit(
        pose=pose,
        centres=model.centres,
        cost=float(r @ r),
        dof=len(r) - PARAMETERS,
        covariance=covariance,
        distances=r[: model.landmarks],
        jacobian=jacobian,
        prior_offsets=r[-2:],
    )


def _friend1_pixel(pose: Poses, centre: tuple[float, float], tangent: Array) -> tuple[Array, Array]:
    """Friend 1 in photo 2 at one pose, ``pi(-K2 R b1)``: pixel (2,) and Jacobian (2, 7),
    NaN when friend 1 is at infinity (in friend 2's image plane); ``tangent``: (3, 2)
    tangent basis of friend 2's direction."""
    log_f1, log_f2 = pose.log_focals[0].tolist()
    f2, ratio = math.exp(log_f2), math.exp(pose.reference - log_f1)
    ux, uy, uz = pose.friend2[0].tolist()
    (ax, bx), (ay, by), (az, bz) = tangent.tolist()
    # b1, its steps along the tangent basis and d b1 / d ln f1, as columns; v = -R b1.
    columns = [
        [ratio * ux, ratio * ax, ratio * bx, -ratio * ux],
        [ratio * uy, ratio * ay, ratio * by, -ratio * uy],
        [uz, az, bz, 0.0],
    ]
    moved = -pose.rotation[0] @ np.array(columns)  # v, then its derivatives
    x, y, z = moved[:, 0].tolist()
    if abs(z) <= _AT_INFINITY * math.sqrt(x * x + y * y + z * z):
        return np.full(2, np.nan), np.full((2, PARAMETERS), np.nan)
    d_project = np.array([[f2 / z, 0.0, -f2 * x / (z * z)], [0.0, f2 / z, -f2 * y / (z * z)]])
    jacobian = np.empty((2, PARAMETERS))
    jacobian[:, _ROTATION] = d_project @ np.array(_skew(-x, -y, -z))  # dv = dw x v
    jacobian[:, 3:6] = d_project @ moved[:, 1:]  # friend 2's steps, then ln f1
    jacobian[:, _FOCAL2] = f2 * x / z, f2 * y / z
    return np.array([centre[0] + f2 * x / z, centre[1] + f2 * y / z]), jacobian


def friend1_positions(poses: Poses, centre: Array) -> Array:
    """(K, 2) friend 1 in photo 2, ``pi(-K2 R b1)``, without derivatives (NaN at infinity,
    as :func:`_friend1_pixel`)."""
    f2 = np.exp(poses.log_focals[:, 1])
    v = -np.einsum("kij,kj->ki", poses.rotation, poses.baseline)
    v[np.abs(v[:, 2]) <= _AT_INFINITY * np.sqrt(np.einsum("ki,ki->k", v, v)), 2] = np.nan
    return centre + f2[:, None] * v[:, :2] / v[:, 2:]


def _friend2_positions(poses: Poses, centre: Array) -> Array:
    """(K, 2) friend 2 in photo 1, ``pi(K1 b1) = pi(K_reference u)``, without derivatives."""
    u = poses.friend2
    return centre + math.exp(poses.reference) * u[:, :2] / u[:, 2:]


def _friend2_pixel(pose: Poses, centre: tuple[float, float], tangent: Array) -> tuple[Array, Array]:
    """Friend 2 in photo 1 at one pose, ``pi(K1 b1) = pi(K_reference u)``: pixel (2,) and
    Jacobian (2, 7), which depends on friend 2's direction alone."""
    reference = math.exp(pose.reference)
    x, y, z = pose.friend2[0].tolist()
    scale = reference / z
    d_project = np.array([[scale, 0.0, -scale * x / z], [0.0, scale, -scale * y / z]])
    jacobian = np.zeros((2, PARAMETERS))
    jacobian[:, _BASELINE] = d_project @ tangent
    return np.array([centre[0] + scale * x, centre[1] + scale * y]), jacobian


def _landmarks(pose: Poses, model: PinholeModel, tangent: Array) -> tuple[Array, Array]:
    """Whitened Sampson distances (N,) and their exact Jacobian (N, 7) at one pose.

    F and its derivatives along the 7 parameters are stacked as eight pixel matrices, so
    every landmark's residual and gradient come from a few products (this runs at every
    iteration of every fit). ``tangent``: (3, 2) tangent basis of friend 2's direction.
    """
    stacked = fundamental_stack(pose, model.centre_pixels, tangent)
    lines2 = stacked @ model.p_t[0]  # (8, 3, N): F p and its derivatives
    lines1 = stacked.transpose(0, 2, 1) @ model.q_t[0]  # F^T q
    eps = np.einsum("kin,in->kn", lines2, model.q_t[0])  # (8, N): q^T F p and derivatives
    # Sampson: eps over its standard deviation g^T C g, g = (F^T q, F p)_xy its gradient in
    # the four tap coordinates and C both taps' covariances (block diagonal, (4, 4, N)).
    gradients = np.concatenate([lines1[:, :2], lines2[:, :2]], axis=1)  # (8, 4, N)
    weighted = np.einsum("ijn,jn->in", model.cov_t, gradients[0])  # C g, (4, N)
    products = np.einsum("kin,in->kn", gradients, weighted)  # g^T C g, then g_k^T C g
    scale = 1.0 / np.sqrt(products[0])  # (N,)
    r = eps[0] * scale
    # d(eps / sqrt(v)) = d eps / sqrt(v) - eps d v / (2 v^1.5), with d v = 2 g_k^T C g.
    return r, (eps[1:] * scale - (r * scale * scale) * products[1:]).T


def fundamental_stack(
    pose: Poses, centres: tuple[tuple[float, float], tuple[float, float]], tangent: Array
) -> Array:
    """(8, 3, 3) F in pixels at one pose (not normalised), then its derivatives along the 7
    tangent parameters (rotation, friend 2's direction, log focal lengths).

    ``centres``: the principal points of photo 1 and 2, px; ``tangent``: (3, 2) tangent
    basis of friend 2's direction.
    """
    log_f1, log_f2 = pose.log_focals[0].tolist()
    f1, f2 = math.exp(log_f1), math.exp(log_f2)
    (x1, y1), (x2, y2) = centres
    inverse1 = np.array([[1.0 / f1, 0.0, -x1 / f1], [0.0, 1.0 / f1, -y1 / f1], [0.0, 0.0, 1.0]])
    inverse2_t = np.array([[1.0 / f2, 0.0, 0.0], [0.0, 1.0 / f2, 0.0], [-x2 / f2, -y2 / f2, 1.0]])
    # b1 = diag(r, r, 1) u, its steps along the tangent basis, and d b1 / d ln f1, as one
    # call for all four cross-product matrices (plain floats: these are 3-vectors).
    ratio = math.exp(pose.reference - log_f1)
    ux, uy, uz = pose.friend2[0].tolist()
    (ax, bx), (ay, by), (az, bz) = tangent.tolist()
    skews = np.array(
        [
            _skew(ratio * ux, ratio * uy, uz),
            _skew(ratio * ax, ratio * ay, az),
            _skew(ratio * bx, ratio * by, bz),
            _skew(-ratio * ux, -ratio * uy, 0.0),
        ]
    )
    moved = pose.rotation[0] @ skews  # R [b1]x = E, then R [.]x of b1's three derivatives
    essential = moved[0]
    # K2^-T M K1^-1 for each M below is F, then dF along each parameter. d K1^-1 / d ln f1
    # is -P K1^-1 and d K2^-T / d ln f2 is -K2^-T P, with P = diag(1, 1, 0); ln f1 also
    # moves b1 (friend 2's pixel stays).
    middle = np.empty((8, 3, 3))
    middle[0] = essential
    middle[1:4] = _BASIS_SKEWS @ essential  # d exp([w]x) R = [e_k]x R
    middle[4:7] = moved[1:4]
    middle[6, :, :2] -= essential[:, :2]  # - E P
    middle[7, :2], middle[7, 2] = -essential[:2], 0.0  # - P E
    return inverse2_t @ middle @ inverse1


def _inverse_k(focal: Array, centre: Array) -> Array:
    """(K, 3, 3) K^-1 for focal lengths (K,) and one principal point (2,)."""
    inverse = np.zeros((len(focal), 3, 3))
    inverse[:, 0, 0] = inverse[:, 1, 1] = 1.0 / focal
    inverse[:, :2, 2] = -centre / focal[:, None]
    inverse[:, 2, 2] = 1.0
    return inverse


def _tangent(x: float, y: float, z: float) -> list[list[float]]:
    """(3, 2) as rows: an orthonormal basis of the plane orthogonal to a unit vector, in
    plain floats (numpy's cross product costs more than all of this)."""
    fx, fy, fz = (-z, 0.0, x) if abs(x) >= 0.9 else (0.0, z, -y)
    norm = math.sqrt(fx * fx + fy * fy + fz * fz)
    fx, fy, fz = fx / norm, fy / norm, fz / norm
    return [[fx, y * fz - z * fy], [fy, z * fx - x * fz], [fz, x * fy - y * fx]]


def _exp(x: float) -> float:
    """``math.exp`` that overflows to infinity as numpy's does."""
    return math.exp(x) if x < _LOG_RANGE else math.inf


def _skew(x: float, y: float, z: float) -> list[list[float]]:
    """The cross-product matrix of one vector, as nested lists (for one ``np.array`` call)."""
    return [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]]


def _skews(v: Array) -> Array:
    """(K, 3, 3) cross-product matrices of (K, 3) vectors."""
    s = np.zeros((len(v), 3, 3))
    s[:, 0, 1], s[:, 0, 2] = -v[:, 2], v[:, 1]
    s[:, 1, 0], s[:, 1, 2] = v[:, 2], -v[:, 0]
    s[:, 2, 0], s[:, 2, 1] = -v[:, 1], v[:, 0]
    return s


_BASIS_SKEWS = _skews(np.eye(3))  # [e_k]x


def _k(focal: float, centre: Array) -> Array:
    return np.array([[focal, 0.0, centre[0]], [0.0, focal, centre[1]], [0.0, 0.0, 1.0]])
