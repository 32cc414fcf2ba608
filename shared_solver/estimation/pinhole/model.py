"""The pinhole model's whitened residuals: how far every tap is from what a pose predicts.

Every tap counts with its own covariance: a landmark by its Sampson distance (Hartley &
Zisserman 11.4.3) whitened by the covariances of its two taps, the friends' marks by their
offset from the model's epipoles (:mod:`.predictions`), both phones' gravity (when measured)
by how far the pose turns one reading from the other, both phones' compass headings (when
measured, with gravity) by how far it turns one north from the other, and each log focal
length by its
offset from the camera's prior (:mod:`..camera`). The sum of their squares is the cost that
:mod:`.fit` minimises.

Everything runs on a batch of K poses and K sets of taps at once: K = 1 for a fit, several
for scoring the exact solvers' poses (:mod:`.starts`), and K sets of re-made taps
for the bootstrap (:mod:`..bootstrap`), so all use the same code.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ...minimal.gravity_and_one import north
from ...projective import Array
from ..camera import FocalPrior
from ..taps import Gravity, Heading, Taps
from .pose import (
    FOCAL1,
    FOCAL2,
    LOG_RANGE,
    PARAMETERS,
    ROTATION,
    Poses,
    skews,
    tangent_basis,
)
from .predictions import (
    friend1_pixel,
    friend1_positions,
    friend2_pixel,
    friend2_positions,
    fundamental_stack,
)


class PinholeModel:
    """Whitened residuals and their Jacobian for K sets of taps under one pair of priors.

    Args:
        taps: the taps; their covariances are shared by the whole batch.
        priors: the focal priors of photo 1 and photo 2 (centres = principal points).
        p, q: (K, N, 2) landmark positions per batch member (default: the taps', K = 1).
        epipole1, epipole2: (K, 2) the friends' marks per member (default: the taps').
        readings: (K, 3) standard normal draws re-making the phones' readings per member
            (the bootstrap): gravity's two whitened residuals, then the compass's; default
            none, the readings as measured.
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
        readings: Array | None = None,
    ) -> None:
        self.taps, self.priors = taps, priors
        self.readings = readings
        self.p = taps.p[None] if p is None else p  # (K, N, 2)
        self.q = taps.q[None] if q is None else q
        self.centres = np.array([priors[0].centre, priors[1].centre])
        self.centre_pixels = (priors[0].centre, priors[1].centre)
        self.prior_mean = np.array([priors[0].log_focal, priors[1].log_focal])
        self.prior_sigma = np.array([priors[0].log_sigma, priors[1].log_sigma])
        self.prior_jacobian = np.zeros((2, PARAMETERS))
        self.prior_jacobian[0, FOCAL1], self.prior_jacobian[1, FOCAL2] = 1.0 / self.prior_sigma
        whiten2, whiten1 = taps.mark_whiteners
        self.friend2 = _Mark.of(taps.epipole1, whiten2, epipole1)
        self.friend1 = _Mark.of(taps.epipole2, whiten1, epipole2)
        self.line = None
        if taps.line1 is not None:
            self.line = taps.line1 / (math.hypot(taps.line1[0], taps.line1[1]) * taps.line_sigma)
        self.landmarks = len(taps)
        self.gravity = None if taps.gravity is None else _Down.of(taps.gravity)
        self.compass = None
        if taps.gravity is not None and taps.heading is not None:
            self.compass = _Compass.of(taps.gravity, taps.heading)
        marks = (
            2 * (self.friend2 is not None)
            + (self.line is not None)
            + 2 * (self.friend1 is not None)
            + 2 * (self.gravity is not None)
            + (self.compass is not None)
        )
        self.residual_count = self.landmarks + marks + 2  # landmarks, marks, focal priors
        # The compass's row is the last before the focal priors'.
        self.compass_row = self.residual_count - 3 if self.compass is not None else None

    def residuals(self, pose: Poses) -> tuple[Array, Array]:
        """(r (M,), J (M, 7)) at one pose: landmarks first, then the friends' marks and the
        priors."""
        r = np.empty(self.residual_count)
        jacobian = np.empty((self.residual_count, PARAMETERS))
        log_f1, log_f2 = pose.log_focals[0].tolist()
        if not max(abs(log_f1), abs(log_f2), abs(pose.reference - log_f1)) < LOG_RANGE:
            r[:], jacobian[:] = np.nan, np.nan
            return r, jacobian
        tangent = np.array(tangent_basis(*pose.friend2[0].tolist()))
        row = self.landmarks
        r[:row], jacobian[:row] = _landmarks(pose, self, tangent)
        if self.friend2 is not None or self.line is not None:
            position, d_position = friend2_pixel(pose, self.centre_pixels[0], tangent)
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
            position, d_position = friend1_pixel(pose, self.centre_pixels[1], tangent)
            r[row : row + 2], jacobian[row : row + 2] = self.friend1.residuals(position, d_position)
            row += 2
        if self.gravity is not None:
            r[row : row + 2], jacobian[row : row + 2] = self.gravity.residuals(pose.rotation[0])
            row += 2
        if self.compass is not None:
            r[row], jacobian[row] = self.compass.residual(pose.rotation[0])
            row += 1
        r[row:] = (pose.log_focals[0] - self.prior_mean) / self.prior_sigma
        jacobian[row:] = self.prior_jacobian
        return r, jacobian

    def offsets(self, poses: Poses) -> Array:
        """(K, M) whitened residuals, without the Jacobian: K poses against one set of taps
        (scoring candidate poses), or one pose against K sets of taps (the bootstrap)."""
        count = max(len(poses), len(self.p))
        out = np.empty((count, self.residual_count))
        out[:, : self.landmarks] = self._sampson(poses)
        column = self.landmarks
        if self.friend2 is not None or self.line is not None:
            position = friend2_positions(poses, self.centres[0])
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
        # A reading made again with fresh noise moves its whitened residual by that noise.
        if self.gravity is not None:
            out[:, column : column + 2] = self.gravity.offsets(poses.rotation)
            if self.readings is not None:
                out[:, column : column + 2] -= self.readings[:, :2]
            column += 2
        if self.compass is not None:
            out[:, column] = self.compass.offsets(poses.rotation)
            if self.readings is not None:
                out[:, column] -= self.readings[:, 2]
            column += 1
        out[:, column:] = (poses.log_focals - self.prior_mean) / self.prior_sigma
        return out

    @functools.cached_property
    def centred_taps(self) -> tuple[Array, Array]:
        """(N, 2) the landmark taps of photo 1 and photo 2 from their principal points, px
        (the taps', not a batch's)."""
        return self.taps.p - self.centres[0], self.taps.q - self.centres[1]

    @functools.cached_property
    def p_t(self) -> Array:
        """(K, 3, N) photo 1's landmarks, homogeneous, as columns."""
        return _columns(self.p)

    @functools.cached_property
    def q_t(self) -> Array:
        """(K, 3, N) photo 2's landmarks, homogeneous, as columns."""
        return _columns(self.q)

    @property
    def cov_t(self) -> Array:
        """(4, 4, N) both taps' covariances of each landmark, block diagonal: a view of
        :attr:`_covariances`, landmark last."""
        return self._covariances.transpose(1, 2, 0)

    @functools.cached_property
    def _covariances(self) -> Array:
        """(N, 4, 4) both taps' covariances of each landmark, block diagonal."""
        covariances = np.zeros((self.landmarks, 4, 4))
        covariances[:, :2, :2], covariances[:, 2:, 2:] = self.taps.cov_p, self.taps.cov_q
        return covariances

    @functools.cached_property
    def _centred(self) -> tuple[Array, Array]:
        """(K, 3, N) the landmarks of photo 1 and photo 2 from their principal points,
        homogeneous, as columns (:meth:`_sampson`)."""
        return _columns(self.p - self.centres[0]), _columns(self.q - self.centres[1])

    def _sampson(self, poses: Poses) -> Array:
        """(K, N) the landmarks' whitened Sampson distances (as :func:`_landmarks`, without
        the Jacobian), for K poses, or one pose and K sets of taps.

        ``F = K2^-T E K1^-1`` with ``K^-1 = diag(1/f, 1/f, 1) T``, ``T`` the shift to the
        principal point; with the taps already shifted (:attr:`_centred`), ``F`` is ``E``
        with its rows and columns scaled, and ``F p``, ``F^T q`` keep their x, y parts
        (the Sampson gradient) and ``q^T F p``. This runs on the bootstrap's samples and on
        every start: fewer products than ``_landmarks``.
        """
        inverse = np.ones((len(poses), 2, 3))  # diag(1/f, 1/f, 1) of photo 1, then photo 2
        inverse[:, :, :2] = np.exp(-poses.log_focals)[:, :, None]
        essential = poses.rotation @ skews(poses.baseline)
        fundamental = essential * inverse[:, 1, :, None] * inverse[:, 0, None, :]
        centred1, centred2 = self._centred
        lines2 = fundamental @ centred1  # (K, 3, N): F p
        lines1 = fundamental.transpose(0, 2, 1) @ centred2  # F^T q
        eps = np.einsum("kin,kin->kn", lines2, centred2)
        # g^T C g as N products of (K, 4) by (4, 4): numpy's einsum over a (4, 4, N) C
        # takes twice as long.
        gradients = np.concatenate([lines1[:, :2], lines2[:, :2]], axis=1).transpose(2, 0, 1)
        variance = np.einsum("nki,nki->kn", gradients @ self._covariances, gradients)
        result: Array = eps / np.sqrt(variance)
        return result


@dataclass(frozen=True)
class _Mark:
    """A friend's mark: where it was tapped (per batch member) and its whitener."""

    position: Array  # (K, 2)
    whiten: Array  # (2, 2)

    @classmethod
    def of(cls, tap: Array | None, whiten: Array | None, batch: Array | None) -> _Mark | None:
        if tap is None or whiten is None:
            return None
        return cls(tap[None] if batch is None else batch, whiten)

    def residuals(self, model: Array, jacobian: Array) -> tuple[Array, Array]:
        """Whitened offset (2,) of the model's pixel (2,) from the mark, and its Jacobian."""
        return self.whiten @ (model - self.position[0]), self.whiten @ jacobian


@dataclass(frozen=True)
class _Down:
    """Both phones' gravity as a residual: photo 1's reading carried into frame 2 by the
    pose, ``R g1``, against photo 2's, ``g2``, along two axes orthogonal to ``g2`` (radians,
    over the two readings' joint sigma). Two residuals, no parameter: the true vertical is
    marginalised to first order."""

    gravity1: Array  # (3,)
    across: Array  # (2, 3) rows: orthonormal, orthogonal to g2, over the sigma

    @classmethod
    def of(cls, gravity: Gravity) -> _Down:
        across = np.array(tangent_basis(*gravity.gravity2.tolist())).T / gravity.sigma
        return cls(gravity.gravity1, across)

    def residuals(self, rotation: Array) -> tuple[Array, Array]:
        """(2,) residuals at one rotation (3, 3), and their Jacobian (2, 7): a step ``w``
        turns ``R g1`` by ``w x R g1``."""
        carried = rotation @ self.gravity1
        jacobian = np.zeros((2, PARAMETERS))
        jacobian[:, ROTATION] = -self.across @ skews(carried[None])[0]
        return self.across @ carried, jacobian

    def offsets(self, rotations: Array) -> Array:
        """(K, 2) residuals at K rotations (K, 3, 3)."""
        result: Array = (rotations @ self.gravity1) @ self.across.T
        return result


@dataclass(frozen=True)
class _Compass:
    """Both phones' compass headings as a residual: photo 1's north carried into frame 2 by
    the pose, ``m = R n1``, against photo 2's, ``n2``: the angle from ``n2`` to ``m`` about
    down (``g2``), over the two headings' joint sigma. One residual, no parameter; how far
    ``m`` tilts out of the level is gravity's residual."""

    north1: Array  # (3,)
    north2: Array  # (3,)
    down2: Array  # (3,)
    sigma: float

    @classmethod
    def of(cls, gravity: Gravity, heading: Heading) -> _Compass:
        return cls(
            north(gravity.gravity1, heading.heading1),
            north(gravity.gravity2, heading.heading2),
            gravity.gravity2,
            heading.sigma,
        )

    def residual(self, rotation: Array) -> tuple[float, Array]:
        """The residual at one rotation (3, 3), and its Jacobian (7,): a step ``w`` moves
        ``m`` by ``w x m``, which turns it about down by ``(g2 x m) . (w x m) / |m_h|^2``,
        ``= w . (g2 - (g2 . m) m) / |m_h|^2`` for a unit ``m`` (``m_h``: its level part)."""
        carried = rotation @ self.north1
        along = float(self.down2 @ carried)
        jacobian = np.zeros(PARAMETERS)
        jacobian[ROTATION] = (self.down2 - along * carried) / ((1.0 - along * along) * self.sigma)
        return float(self.offsets(rotation[None])[0]), jacobian

    def offsets(self, rotations: Array) -> Array:
        """(K,) residuals at K rotations (K, 3, 3), each angle in (-pi, pi] over the sigma."""
        carried = rotations @ self.north1  # (K, 3)
        sine = np.cross(self.north2, carried) @ self.down2
        result: Array = np.arctan2(sine, carried @ self.north2) / self.sigma
        return result


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


def _columns(points: Array) -> Array:
    """(K, 3, N) pixels (K, N, 2) as homogeneous columns."""
    count, landmarks, _ = points.shape
    columns = np.ones((count, 3, landmarks))
    columns[:, :2] = points.transpose(0, 2, 1)
    return columns
