"""The maximum a posteriori pinhole geometry: the fit over every tap and both focal priors,
and what it gives (F, the epipoles, the focal lengths, their covariances).

The minimum of the sum of squared whitened residuals (:mod:`.model`) is the maximum a
posteriori estimate to first order, and the inverse of ``J^T J`` its covariance (the Laplace
approximation), propagated to what the answer shows by :mod:`.propagation`.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ... import linalg
from ...projective import Array
from ..least_squares import levenberg_marquardt
from .model import PinholeModel
from .pose import LOG_RANGE, PARAMETERS, Poses, skews
from .propagation import friend1_covariance, fundamental_covariance

# The cost is a chi-square: stop when a step gains less than 1e-6 of it (the estimate then
# moves by about 1e-3 of its own sigma), or 1e-16 on exact taps (1e-8 sigma).
_GAIN_TOLERANCE = (1e-5, 1e-16)
# A fit whose focal lengths end this many prior sigmas away ran off (e^5 = 150 times).
_FOCAL_RANGE_SIGMAS = 10.0


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

    @functools.cached_property
    def usable(self) -> bool:
        """Whether the fit is a number throughout, with focal lengths within ten prior
        sigmas: a start far from any geometry can run off to absurd ones."""
        return bool(
            math.isfinite(self.cost)
            and np.isfinite(self.covariance).all()
            and np.isfinite(self.jacobian).all()
            and np.isfinite(self.pose.rotation).all()
            and (np.abs(self.distances) < np.inf).all()
            and (np.abs(self.prior_offsets) <= _FOCAL_RANGE_SIGMAS).all()
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
        (f1, f2), (c1, c2) = self.focals, self.centres
        essential = self.pose.rotation[0] @ skews(self.pose.baseline)[0]
        f = _k_inverse(f2, c2).T @ essential @ _k_inverse(f1, c1)
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
        """(9, 9) first-order covariance of :attr:`fundamental` read row by row
        (:func:`.propagation.fundamental_covariance`)."""
        return fundamental_covariance(self.pose, self.centres, self.covariance)

    @functools.cached_property
    def covariance2(self) -> Array | None:
        """(2, 2) px^2 covariance of friend 1's pixel position, None if it is at infinity."""
        return friend1_covariance(self.pose, self.centres, self.covariance)


def fit_pinhole(model: PinholeModel, start: Poses, *, max_iterations: int = 50) -> PinholeFit:
    """Refine a pose over every tap and both focal priors.

    Args:
        model: the taps (landmarks, N >= 1, and whichever friends' marks were made, with
            covariances) and the focal priors of photo 1 and photo 2 (their centres are the
            principal points).
        start: an initial pose (a batch of one), e.g. from :mod:`...minimal.epipole_and_three`.
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
    if not np.isfinite(information).all():
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


def _exp(x: float) -> float:
    """``math.exp`` that overflows to infinity as numpy's does."""
    return math.exp(x) if x < LOG_RANGE else math.inf


def _k(focal: float, centre: Array) -> Array:
    return np.array([[focal, 0.0, centre[0]], [0.0, focal, centre[1]], [0.0, 0.0, 1.0]])


def _k_inverse(focal: float, centre: Array) -> Array:
    """(3, 3) the inverse of :func:`_k`, in closed form: an LU solve calls K singular when
    the focal length is tiny against the principal point (a focal told in thousandths of a
    millimetre: 5e-37 px against 800 px), where this is exact."""
    return np.array(
        [
            [1.0 / focal, 0.0, -centre[0] / focal],
            [0.0, 1.0 / focal, -centre[1] / focal],
            [0.0, 0.0, 1.0],
        ]
    )
