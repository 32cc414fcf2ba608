"""Landmarks on one plane (floor, wall, stage front): ``e2 = H e1``.

If every landmark is on one plane, ``q = H p`` and friend 1's position is ``e2 = H e1``
exactly (the line from friend 1 through friend 2 meets the plane in a point seen at
``e1`` by friend 1 and at ``e2`` by friend 2). Measured here: with friend 2's tap the
F-based system stays well-posed on a plane (one null vector, unlike the classical system
without ``e1``), but the homography has fewer degrees of freedom: on floor scenes at 1 px it
gives a median error of 15 px against 24 px with five landmarks (8.5 against 10.6 with six),
and on a frontal wall 2.7 against 6.5. So ``solve`` uses it whenever the taps are consistent
with one plane (:func:`coplanar_fit`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import linalg
from ..errors import Reason
from ..linalg import whitener2
from ..projective import Array, hartley_normaliser, homogeneous
from ..refusal import SolverError
from .least_squares import gauge_free_covariance, levenberg_marquardt
from .taps import Taps
from .uncertainty import chi2_quantile

_REWEIGHTINGS = 2
# A linear fit this many times over the chi-square threshold is not worth refining.
_SCREEN = 4.0


@dataclass(frozen=True)
class PlanarFit:
    """A homography between the photos, fitted to the landmarks.

    Attributes:
        homography: (3, 3) H in pixels, unit Frobenius norm, ``q ~ H p``.
        errors: (N,) length of each landmark's whitened transfer error, px.
        cost: sum of squared whitened transfer errors, px^2.
        dof: ``2 N - 8``.
    """

    homography: Array
    errors: Array
    cost: float
    dof: int
    normalised: Array  # H between Hartley-normalised coordinates, and its covariance
    covariance: Array
    t1: Array
    t2: Array

    def friend1(self, epipole1_tap: Array, tap_covariance: Array) -> tuple[Array, Array | None]:
        """``e2 = H e1`` (3,) and its (2, 2) px^2 covariance (None at infinity).

        The covariance combines H's and the tap's on friend 2 (``tap_covariance``, (2, 2) px^2).
        """
        e1 = np.append(epipole1_tap, 1.0)
        e1_n = self.t1 @ e1
        e2 = linalg.solve(self.t2, self.normalised @ e1_n)
        if abs(e2[2]) < 1e-9 * linalg.norm(e2):
            return e2, None
        dehomogenise = np.array([[1.0, 0.0, -e2[0] / e2[2]], [0.0, 1.0, -e2[1] / e2[2]]]) / e2[2]
        lead = dehomogenise @ linalg.inv(self.t2)
        d_h = lead @ np.kron(np.eye(3), e1_n)  # d e2 / d vec(H), row-major vec
        d_e1 = lead @ self.normalised @ self.t1[:, :2]  # d e2 / d (pixel e1)
        return e2, d_h @ self.covariance @ d_h.T + d_e1 @ tap_covariance @ d_e1.T


def coplanar_fit(taps: Taps) -> PlanarFit | None:
    """The landmarks' homography if one plane explains them within tap noise, else None.

    The maximum-likelihood fit must pass a chi-square test at 0.99 (measured on exactly
    planar floor scenes: chosen in 97-99 % of them; on 3-D facing scenes in under 2 %, only
    with five landmarks). A linear fit first screens out clearly non-planar scenes, which
    saves the ML fit on almost every solve.

    Args:
        taps: landmarks (N <= 4 never tells: None) with their covariances.
    """
    dof = 2 * len(taps) - 8
    if dof <= 0:
        return None
    threshold = chi2_quantile(0.99, dof)
    if float(plane_cost(taps).sum()) > _SCREEN * threshold:
        return None
    fit = fit_planar(taps)
    return fit if fit.cost <= threshold else None


def plane_cost(taps: Taps) -> Array:
    """(N,) squared whitened transfer errors (unit variance) of the linear homography."""
    frame = _PlaneFrame.of(taps.p, taps.q)
    h_n = frame.start()
    transfer, _ = _transfer(h_n, frame.p, frame.q)
    white = np.einsum("nij,nj->ni", _whitening(h_n, frame, taps), transfer)
    return np.einsum("ni,ni->n", white, white) / frame.s2**2


def fit_planar(taps: Taps) -> PlanarFit:
    """Maximum-likelihood homography from N >= 4 landmarks, with its covariance.

    Each landmark's transfer error ``H p - q`` is whitened by its first-order covariance
    ``C_q + J C_p J^T`` (``J`` = d(Hp)/dp, ``C`` each tap's covariance), so noise in both
    photos counts.

    Args:
        taps: landmarks of photo 1 and photo 2 with their covariances.
    """
    frame = _PlaneFrame.of(taps.p, taps.q)
    theta = frame.start().ravel()
    for _ in range(_REWEIGHTINGS):
        whitening = _whitening(theta.reshape(3, 3), frame, taps)

        def residuals(theta: Array, whitening: Array = whitening) -> tuple[Array, Array]:
            transfer, d_transfer = _transfer(theta.reshape(3, 3), frame.p, frame.q)
            r = np.einsum("nij,nj->ni", whitening, transfer) / frame.s2
            jacobian = np.einsum("nij,njk->nik", whitening, d_transfer) / frame.s2
            return r.ravel(), jacobian.reshape(-1, 9)

        theta, r, jacobian = levenberg_marquardt(
            residuals, theta, renormalise=lambda t: t / linalg.norm(t)
        )
    h_n = theta.reshape(3, 3)
    homography = linalg.solve(frame.t2, h_n) @ frame.t1
    return PlanarFit(
        homography=homography / linalg.norm(homography),
        errors=np.hypot(r[0::2], r[1::2]),
        cost=float(r @ r),
        dof=2 * len(taps) - 8,
        normalised=h_n,
        covariance=gauge_free_covariance(jacobian, theta, 1.0),
        t1=frame.t1,
        t2=frame.t2,
    )


@dataclass(frozen=True)
class _PlaneFrame:
    t1: Array
    t2: Array
    p: Array  # (N, 3) normalised homogeneous photo-1 landmarks
    q: Array  # (N, 2) normalised photo-2 landmarks
    s1: float
    s2: float

    @classmethod
    def of(cls, p: Array, q: Array) -> _PlaneFrame:
        t1, t2 = hartley_normaliser(p), hartley_normaliser(q)
        s1, s2 = float(t1[0, 0]), float(t2[0, 0])
        return cls(t1, t2, homogeneous(p * s1 + t1[:2, 2]), q * s2 + t2[:2, 2], s1, s2)

    def start(self) -> Array:
        """Linear (DLT) homography in normalised coordinates, unit norm (H & Z 4.1)."""
        x, y = self.p[:, 0], self.p[:, 1]
        u, v = self.q[:, 0], self.q[:, 1]
        zero, one = np.zeros_like(x), np.ones_like(x)
        rows = np.empty((2 * len(x), 9))
        rows[0::2] = np.column_stack([x, y, one, zero, zero, zero, -u * x, -u * y, -u])
        rows[1::2] = np.column_stack([zero, zero, zero, x, y, one, -v * x, -v * y, -v])
        _, singular, vt = linalg.svd(rows)
        if len(singular) >= 8 and singular[7] <= 1e-10 * singular[0]:
            raise SolverError(Reason.NO_PLANE)
        return vt[-1].reshape(3, 3)


def _transfer(h: Array, p_n: Array, q_n: Array) -> tuple[Array, Array]:
    """Transfer error ``pi(H p) - q`` (N, 2) and its Jacobian w.r.t. vec(H) (N, 2, 9)."""
    mapped = p_n @ h.T
    w = mapped[:, 2:3]
    projected = mapped[:, :2] / w
    jacobian = np.zeros((len(p_n), 2, 9))
    jacobian[:, 0, 0:3] = p_n / w
    jacobian[:, 1, 3:6] = p_n / w
    jacobian[:, :, 6:9] = -(projected / w)[:, :, None] * p_n[:, None, :]
    return projected - q_n, jacobian


def _whitening(h: Array, frame: _PlaneFrame, taps: Taps) -> Array:
    """(N, 2, 2) inverse Cholesky factors of ``C_q + J C_p J^T`` (px^2, J in px per px)."""
    mapped = frame.p @ h.T
    w = mapped[:, 2]
    projected = mapped[:, :2] / w[:, None]
    # d pi(H p) / d p, in normalised units, then in pixels per pixel
    jacobian = (h[None, :2, :2] - projected[:, :, None] * h[None, 2:3, :2]) / w[:, None, None]
    jacobian *= frame.s1 / frame.s2
    covariance = taps.cov_q + jacobian @ taps.cov_p @ jacobian.transpose(0, 2, 1)
    return whitener2(covariance)
