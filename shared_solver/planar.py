"""Landmarks on one plane (floor, wall, stage front): ``e2 = H e1``.

If every landmark is on one plane, ``q = H p`` and the seeker's position is ``e2 = H e1``
exactly (the line from the seeker through the buddy meets the plane in a point seen at
``e1`` by the seeker and at ``e2`` by the buddy). Measured here: with the buddy's tap
the F-based system stays well-posed on a plane, but the homography has fewer degrees of
freedom and gives a 2-5x smaller error on planar scenes, so ``solve`` picks whichever
model the taps support by :func:`gric`.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from .errors import ErrorCode, SolverError
from .least_squares import gauge_free_covariance, levenberg_marquardt
from .projective import Array, hartley_normaliser, homogeneous

_REWEIGHTINGS = 2


@dataclass(frozen=True)
class PlanarFit:
    """A homography between the photos and the seeker's position it implies.

    Attributes:
        homography: (3, 3) H in pixels, unit Frobenius norm, ``q ~ H p``.
        epipole1: (3,) the buddy's tap, homogeneous (the plane model does not refine it).
        epipole2: (3,) ``H e1``.
        errors: (N,) length of each landmark's whitened transfer error, px.
        cost: sum of squared whitened transfer errors, px^2.
        dof: ``2 N - 8``.
        covariance2: (2, 2) px^2 covariance of e2's pixel position, None at infinity.
    """

    homography: Array
    epipole1: Array
    epipole2: Array
    errors: Array
    cost: float
    dof: int
    covariance2: Array | None


def plane_cost(p: Array, q: Array, *, sigma: float) -> Array:
    """(N,) squared whitened transfer errors (in units of ``sigma^2``) of the linear homography.

    The quick test of whether the landmarks look coplanar, for model selection.
    """
    frame = _PlaneFrame.of(p, q)
    h_n = frame.start()
    transfer, _ = _transfer(h_n, frame.p, frame.q)
    white = np.einsum("nij,nj->ni", _whitening(h_n, frame.p, frame.s1 / frame.s2), transfer)
    return np.einsum("ni,ni->n", white, white) / (frame.s2 * sigma) ** 2


def fit_planar(p: Array, q: Array, epipole1_tap: Array, *, sigma: float) -> PlanarFit:
    """Maximum-likelihood homography from N >= 4 landmarks, and ``e2 = H e1``.

    Each landmark's transfer error ``H p - q`` is whitened by its first-order covariance
    ``sigma^2 (I + J J^T)`` (``J`` = d(Hp)/dp), so noise in both photos counts.

    Args:
        p, q: (N, 2) landmarks of photo 1 and photo 2, pixels.
        epipole1_tap: (2,) the buddy's tap in photo 1.
        sigma: tap noise, px.
    """
    frame = _PlaneFrame.of(p, q)
    theta = frame.start().ravel()
    for _ in range(_REWEIGHTINGS):
        whitening = _whitening(theta.reshape(3, 3), frame.p, frame.s1 / frame.s2)

        def residuals(theta: Array, whitening: Array = whitening) -> tuple[Array, Array]:
            transfer, d_transfer = _transfer(theta.reshape(3, 3), frame.p, frame.q)
            r = np.einsum("nij,nj->ni", whitening, transfer) / frame.s2
            jacobian = np.einsum("nij,njk->nik", whitening, d_transfer) / frame.s2
            return r.ravel(), jacobian.reshape(-1, 9)

        theta, r, jacobian = levenberg_marquardt(
            residuals, theta, renormalise=lambda t: t / np.linalg.norm(t)
        )
    h_n = theta.reshape(3, 3)
    homography = np.linalg.solve(frame.t2, h_n) @ frame.t1
    homography /= np.linalg.norm(homography)
    e1 = np.append(epipole1_tap, 1.0)
    e2 = homography @ e1
    covariance = gauge_free_covariance(jacobian, theta, sigma)
    return PlanarFit(
        homography=homography,
        epipole1=e1,
        epipole2=e2,
        errors=np.linalg.norm(r.reshape(-1, 2), axis=1),
        cost=float(r @ r),
        dof=2 * len(p) - 8,
        covariance2=_e2_covariance(h_n, frame.t1, frame.t2, e1, covariance=covariance, sigma=sigma),
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
        """Linear (DLT) homography in normalised coordinates, unit norm."""
        start, _ = cv2.findHomography(self.p[:, :2], self.q, 0)
        if start is None:
            raise SolverError(ErrorCode.DEGENERATE_CONFIGURATION, "No plane fits these landmarks.")
        return start / np.linalg.norm(start)


def gric(squared: Array, *, dimension: int, parameters: int) -> float:
    """Torr's geometric robust information criterion (lower is the better model).

    Args:
        squared: (N,) squared residuals in units of ``sigma^2``, one per landmark.
        dimension: dimension of the model's manifold in the 4-D space of a landmark pair
            (F: 3, H: 2).
        parameters: the model's degrees of freedom (F: 7, H: 8).
    """
    data = 4
    n = len(squared)
    robust = np.minimum(squared, 2.0 * (data - dimension))
    return float(robust.sum() + np.log(data) * dimension * n + np.log(data * n) * parameters)


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


def _whitening(h: Array, p_n: Array, pixel_ratio: float) -> Array:
    """(N, 2, 2) inverse Cholesky factors of ``I + J J^T`` (J in pixels per pixel)."""
    mapped = p_n @ h.T
    w = mapped[:, 2]
    projected = mapped[:, :2] / w[:, None]
    # d pi(H p) / d p, in normalised units, then in pixels per pixel
    jacobian = (h[None, :2, :2] - projected[:, :, None] * h[None, 2:3, :2]) / w[:, None, None]
    jacobian *= pixel_ratio
    covariance = np.eye(2) + jacobian @ jacobian.transpose(0, 2, 1)
    return np.linalg.inv(np.linalg.cholesky(covariance))


def _e2_covariance(
    h_n: Array, t1: Array, t2: Array, e1: Array, *, covariance: Array, sigma: float
) -> Array | None:
    """(2, 2) px^2 covariance of ``e2 = H e1`` from H's covariance and the tap's noise."""
    e1_n = t1 @ e1
    e2_n = h_n @ e1_n
    e2 = np.linalg.solve(t2, e2_n)
    if abs(e2[2]) < 1e-9 * np.linalg.norm(e2):
        return None
    to_pixels = np.linalg.inv(t2)
    dehomogenise = np.array([[1.0, 0.0, -e2[0] / e2[2]], [0.0, 1.0, -e2[1] / e2[2]]]) / e2[2]
    lead = dehomogenise @ to_pixels
    d_h = lead @ np.kron(np.eye(3), e1_n)  # d e2 / d vec(H), row-major vec
    d_e1 = lead @ h_n @ t1[:, :2]  # d e2 / d (pixel e1)
    return d_h @ covariance @ d_h.T + sigma**2 * d_e1 @ d_e1.T
