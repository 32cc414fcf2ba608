"""Maximum-likelihood epipolar geometry over every tap, with its first-order uncertainty.

Each landmark contributes its Sampson distance (the first-order distance from the taps to
the nearest pair of points that fit F exactly; Hartley & Zisserman 11.4.3) whitened by the
covariances of its two taps, and friend 2's tap contributes its own whitened offset: the
tap on friend 2 is as noisy as any other. Every residual then has unit variance, so the
least-squares minimum is the maximum-likelihood estimate to first order, its cost a
chi-square, and ``(J^T J)^-1`` its covariance.

Parametrisation (normalised coordinates): ``F = [a1 | a2 | -(x a1 + y a2)]`` keeps
``F (x, y, 1)^T = 0`` for any columns ``a1, a2`` and friend 2's position ``(x, y)``: seven
degrees of freedom after the scale of ``(a1, a2)``, and ``e2 = a1 x a2``. When both friends tapped
each other, ``(a1, a2)`` is further tied to ``e2 = (x2, y2, 1)``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from .. import linalg
from ..errors import Reason
from ..projective import Array, hartley_normaliser, homogeneous, right_epipole, skew
from ..refusal import SolverError
from .least_squares import gauge_free_covariance, levenberg_marquardt
from .taps import Taps, whitener

# Beyond this the first-order ellipse of e2 says nothing useful: e2 is effectively at infinity.
_FAR_W = 1e-9


@dataclass(frozen=True)
class EpipolarFit:
    """A fitted geometry in photo pixels.

    Attributes:
        fundamental: (3, 3) F, unit Frobenius norm, ``q^T F p = 0``.
        epipole1, epipole2: (3,) homogeneous epipoles (``F e1 = 0``, ``F^T e2 = 0``).
        distances: (N,) signed whitened Sampson distance of each landmark (in its sigmas).
        cost: sum of squared whitened residuals of landmarks and epipole taps (chi-square).
        dof: residual degrees of freedom (observations minus 7).
        covariance1, covariance2: (2, 2) px^2 covariance of each epipole's pixel position,
            None when that epipole is at infinity.
        parameters: what :attr:`fundamental_covariance` is computed from, when asked: the
            normalised frame, (a1, a2, friend2), d(a1, a2, friend2)/d(theta) and theta's
            covariance (None: not available).
    """

    fundamental: Array
    epipole1: Array
    epipole2: Array
    distances: Array
    cost: float
    dof: int
    covariance1: Array | None
    covariance2: Array | None
    parameters: tuple[_Frame, Array, Array, Array] | None = field(
        default=None, repr=False, compare=False
    )

    @functools.cached_property
    def fundamental_covariance(self) -> Array | None:
        """(9, 9) first-order covariance of ``fundamental`` read row by row (on its unit
        sphere), computed when first asked: most fits (mis-tap searches, ranking) never
        need it."""
        if self.parameters is None:
            return None
        frame, columns, d_columns, covariance = self.parameters
        jacobian = _pixel_f_jacobian(frame, columns[:3], columns[3:6], columns[6:8]) @ d_columns
        return jacobian @ covariance @ jacobian.T


@dataclass(frozen=True)
class _Frame:
    """Hartley-normalised landmarks and how to get back to pixels."""

    t1: Array
    t2: Array
    p: Array  # (N, 2) normalised photo-1 landmarks
    q: Array  # (N, 3) normalised photo-2 landmarks, homogeneous
    s1: float  # normalised units per pixel, photo 1
    s2: float
    cov_p: Array  # (N, 2, 2) tap covariances in normalised units^2
    cov_q: Array

    @classmethod
    def of(cls, taps: Taps) -> _Frame:
        p, q = taps.p, taps.q
        t1, t2 = hartley_normaliser(p), hartley_normaliser(q)
        s1, s2 = float(t1[0, 0]), float(t2[0, 0])
        p_n = p * s1 + t1[:2, 2]
        q_n = np.empty((len(q), 3))
        q_n[:, :2] = q * s2 + t2[:2, 2]
        q_n[:, 2] = 1.0
        return cls(t1, t2, p_n, q_n, s1, s2, taps.cov_p * s1 * s1, taps.cov_q * s2 * s2)

    def normalised_f(self, fundamental: Array) -> Array:
        return linalg.solve(self.t2.T, fundamental) @ linalg.inv(self.t1)

    def pixel_f(self, normalised: Array) -> Array:
        fundamental = self.t2.T @ normalised @ self.t1
        return fundamental / linalg.norm(fundamental)


def _sampson(frame: _Frame, a1: Array, a2: Array, x: float, y: float) -> tuple[Array, Array]:
    """Whitened Sampson distances and their Jacobian w.r.t. (a1, a2, x, y): (N,), (N, 8)."""
    q = frame.q
    u, v = frame.p[:, 0] - x, frame.p[:, 1] - y
    qa1, qa2 = q @ a1, q @ a2  # d eps / d p (normalised)
    fx = u * a1[0] + v * a2[0]  # (F p)_x = d eps / d q_x
    fy = u * a1[1] + v * a2[1]  # (F p)_y
    eps = qa1 * u + qa2 * v  # q^T F p
    # Each tap's covariance times the gradient: the variance of eps is g^T C g.
    cp, cq = frame.cov_p, frame.cov_q
    wp0 = cp[:, 0, 0] * qa1 + cp[:, 0, 1] * qa2
    wp1 = cp[:, 1, 0] * qa1 + cp[:, 1, 1] * qa2
    wq0 = cq[:, 0, 0] * fx + cq[:, 0, 1] * fy
    wq1 = cq[:, 1, 0] * fx + cq[:, 1, 1] * fy
    g2 = qa1 * wp0 + qa2 * wp1 + fx * wq0 + fy * wq1
    # d(eps) and d(g2)/2 w.r.t. (a1, a2, x, y), side by side.
    d_eps = np.empty((len(u), 8))
    d_eps[:, 0:3] = u[:, None] * q
    d_eps[:, 3:6] = v[:, None] * q
    d_eps[:, 6], d_eps[:, 7] = -qa1, -qa2
    half_d_g2 = np.empty((len(u), 8))
    half_d_g2[:, 0:3] = wp0[:, None] * q
    half_d_g2[:, 3:6] = wp1[:, None] * q
    half_d_g2[:, 0] += wq0 * u
    half_d_g2[:, 1] += wq1 * u
    half_d_g2[:, 3] += wq0 * v
    half_d_g2[:, 4] += wq1 * v
    half_d_g2[:, 6] = -(wq0 * a1[0] + wq1 * a1[1])
    half_d_g2[:, 7] = -(wq0 * a2[0] + wq1 * a2[1])
    inv_g = 1.0 / np.sqrt(g2)
    distance = eps * inv_g
    jacobian = (d_eps - (distance * inv_g)[:, None] * half_d_g2) * inv_g[:, None]
    return distance, jacobian


def _unit_block(theta: Array, size: int) -> Array:
    theta = theta.copy()
    theta[:size] /= linalg.norm(theta[:size])
    return theta


def fit_epipolar(taps: Taps, start: Array, *, use_friend2: bool = True) -> EpipolarFit:
    """Refine F over all taps, friend 2's tap (or line) included, and its uncertainty.

    Args:
        taps: landmarks (N >= 7 - the friends' equations) with their covariances, and
            friend 2's tap or a line through friend 2 in photo 1 (friend 1's tap in photo 2
            is not used here: :func:`fit_two_epipoles`).
        start: (3, 3) initial F in pixels (a linear or minimal solution), with a finite e1.
        use_friend2: whether friend 2's tap or line takes part (False: landmarks only).
    """
    frame = _Frame.of(taps)
    f0 = frame.normalised_f(start)
    e1 = right_epipole(f0)
    if abs(e1[2]) < _FAR_W * linalg.norm(e1):
        raise SolverError(Reason.FRIEND_AT_INFINITY)
    x0, y0 = e1[:2] / e1[2]
    prior_rows, prior_target = _prior(frame, taps) if use_friend2 else (None, np.zeros(0))

    def residuals(theta: Array) -> tuple[Array, Array]:
        r, jacobian = _sampson(frame, theta[0:3], theta[3:6], theta[6], theta[7])
        if prior_rows is None:
            return r, jacobian
        r_prior = prior_rows @ np.array([theta[6], theta[7], 1.0]) - prior_target
        j_prior = np.zeros((len(r_prior), 8))
        j_prior[:, 6:8] = prior_rows[:, :2]
        return np.concatenate([r, r_prior]), np.vstack([jacobian, j_prior])

    start_theta = np.concatenate([f0[:, 0], f0[:, 1], [x0, y0]])
    theta, r, jacobian = levenberg_marquardt(
        residuals, start_theta, renormalise=lambda t: _unit_block(t, 6)
    )
    a1, a2 = theta[0:3], theta[3:6]
    # d(a1 x a2) = -[a2]x da1 + [a1]x da2
    d_e2 = np.hstack([-skew(a2), skew(a1), np.zeros((3, 2))])
    d_e1 = np.zeros((3, 8))
    d_e1[0, 6] = d_e1[1, 7] = 1.0
    return _fit(
        frame,
        a1,
        a2,
        friend2=theta[6:8],
        friend1=linalg.cross(a1, a2),
        derivatives=(d_e1, d_e2),
        residuals=(r, jacobian, len(taps)),
        gauge=np.concatenate([a1, a2, [0.0, 0.0]]),
        d_columns=np.eye(8),
    )


def fit_two_epipoles(taps: Taps, start: Array) -> EpipolarFit:
    """Refine F when both friends tapped each other: both taps are refined with the landmarks.

    Args:
        taps: landmarks (N >= 3), the taps on friend 2 (photo 1) and on friend 1
            (photo 2), all with their covariances.
        start: (3, 3) initial F with finite epipoles (e.g. from both taps).
    """
    assert taps.epipole1 is not None
    assert taps.cov_e1 is not None
    assert taps.epipole2 is not None
    assert taps.cov_e2 is not None
    frame = _Frame.of(taps)
    f0 = frame.normalised_f(start)
    e1, e2 = right_epipole(f0), right_epipole(f0.T)
    x1, y1 = e1[:2] / e1[2]
    x2, y2 = e2[:2] / e2[2]
    # F = B2 M B1^T with B = [[1, 0], [0, 1], [-x, -y]]: the top-left 2x2 block of F is M.
    start_theta = np.array([f0[0, 0], f0[0, 1], f0[1, 0], f0[1, 1], x1, y1, x2, y2])
    # The friends' marks in pixels are (normalised - offset) / s: whitened, a linear map of
    # (x1, y1, x2, y2).
    whiten = np.zeros((4, 4))
    whiten[:2, :2] = whitener(taps.cov_e1) / frame.s1
    whiten[2:, 2:] = whitener(taps.cov_e2) / frame.s2
    marks = np.concatenate(
        [
            (frame.t1 @ np.append(taps.epipole1, 1.0))[:2],
            (frame.t2 @ np.append(taps.epipole2, 1.0))[:2],
        ]
    )
    tap_target = whiten @ marks

    def columns(theta: Array) -> tuple[Array, Array]:
        m11, m12, m21, m22, _, _, x2_, y2_ = theta
        return (
            np.array([m11, m21, -(x2_ * m11 + y2_ * m21)]),
            np.array([m12, m22, -(x2_ * m12 + y2_ * m22)]),
        )

    def residuals(theta: Array) -> tuple[Array, Array]:
        m11, m12, m21, m22, x1_, y1_, x2_, y2_ = theta
        a1, a2 = columns(theta)
        r, j_a = _sampson(frame, a1, a2, x1_, y1_)
        # Chain rule from (a1, a2, x1, y1) to (M, x1, y1, x2, y2).
        jacobian = np.zeros((len(r), 8))
        jacobian[:, 0] = j_a[:, 0] - x2_ * j_a[:, 2]  # m11
        jacobian[:, 1] = j_a[:, 3] - x2_ * j_a[:, 5]  # m12
        jacobian[:, 2] = j_a[:, 1] - y2_ * j_a[:, 2]  # m21
        jacobian[:, 3] = j_a[:, 4] - y2_ * j_a[:, 5]  # m22
        jacobian[:, 4:6] = j_a[:, 6:8]
        jacobian[:, 6] = -m11 * j_a[:, 2] - m12 * j_a[:, 5]
        jacobian[:, 7] = -m21 * j_a[:, 2] - m22 * j_a[:, 5]
        r_taps = whiten @ theta[4:8] - tap_target
        return np.concatenate([r, r_taps]), np.vstack(
            [jacobian, np.hstack([np.zeros((4, 4)), whiten])]
        )

    theta, r, jacobian = levenberg_marquardt(
        residuals, start_theta, renormalise=lambda t: _unit_block(t, 4)
    )
    a1, a2 = columns(theta)
    d_e1, d_e2 = np.zeros((3, 8)), np.zeros((3, 8))
    d_e1[0, 4] = d_e1[1, 5] = d_e2[0, 6] = d_e2[1, 7] = 1.0
    m11, m12, m21, m22, _, _, x2, y2 = theta
    # (a1, a2, x1, y1) from theta: a1 = (m11, m21, -(x2 m11 + y2 m21)), a2 likewise.
    d_columns = np.zeros((8, 8))
    d_columns[0, 0] = d_columns[1, 2] = d_columns[3, 1] = d_columns[4, 3] = 1.0
    d_columns[2] = [-x2, 0.0, -y2, 0.0, 0.0, 0.0, -m11, -m21]
    d_columns[5] = [0.0, -x2, 0.0, -y2, 0.0, 0.0, -m12, -m22]
    d_columns[6, 4] = d_columns[7, 5] = 1.0
    return _fit(
        frame,
        a1,
        a2,
        friend2=theta[4:6],
        friend1=np.append(theta[6:8], 1.0),
        derivatives=(d_e1, d_e2),
        residuals=(r, jacobian, len(taps)),
        gauge=np.concatenate([theta[:4], np.zeros(4)]),
        d_columns=d_columns,
    )


def _fit(
    frame: _Frame,
    a1: Array,
    a2: Array,
    *,
    friend2: Array,
    friend1: Array,
    derivatives: tuple[Array, Array],
    residuals: tuple[Array, Array, int],
    gauge: Array,
    d_columns: Array,
) -> EpipolarFit:
    """The fit in pixels from its normalised parameters at the minimum.

    Args:
        a1, a2: columns of F (normalised); friend2: (2,) e1 (normalised); friend1: (3,) e2.
        derivatives: (3, P) Jacobians of e1 and e2 (homogeneous, normalised) w.r.t. theta.
        residuals: (r, J, number of landmarks) at the minimum; gauge: theta's null direction.
        d_columns: (8, P) Jacobian of (a1, a2, friend2) w.r.t. theta.
    """
    r, jacobian, landmarks = residuals
    covariance = gauge_free_covariance(jacobian, gauge, 1.0)
    e1_n = np.append(friend2, 1.0)
    x, y = friend2
    return EpipolarFit(
        fundamental=frame.pixel_f(np.column_stack([a1, a2, -(x * a1 + y * a2)])),
        epipole1=linalg.solve(frame.t1, e1_n),
        epipole2=linalg.solve(frame.t2, friend1),
        distances=r[:landmarks],
        cost=float(r @ r),
        dof=len(r) - 7,
        covariance1=_pixel_covariance(frame.t1, e1_n, derivatives[0], covariance),
        covariance2=_pixel_covariance(frame.t2, friend1, derivatives[1], covariance),
        parameters=(frame, np.concatenate([a1, a2, friend2]), d_columns, covariance),
    )


def _pixel_f_jacobian(frame: _Frame, a1: Array, a2: Array, friend2: Array) -> Array:
    """(9, 8) derivative of the unit pixel F (row by row) w.r.t. (a1, a2, x, y), for
    ``F_n = [a1 | a2 | -(x a1 + y a2)]`` in normalised coordinates."""
    x, y = friend2
    d_normalised = np.zeros((8, 3, 3))  # d F_n along each of the 8 parameters
    for i in range(3):
        d_normalised[i, i, 0], d_normalised[i, i, 2] = 1.0, -x
        d_normalised[3 + i, i, 1], d_normalised[3 + i, i, 2] = 1.0, -y
    d_normalised[6, :, 2], d_normalised[7, :, 2] = -a1, -a2
    raw = frame.t2.T @ np.column_stack([a1, a2, -(x * a1 + y * a2)]) @ frame.t1
    norm = linalg.norm(raw)
    unit = raw.reshape(9) / norm
    d_raw = (frame.t2.T @ d_normalised @ frame.t1).reshape(8, 9).T / norm  # (9, 8)
    return d_raw - np.outer(unit, unit @ d_raw)


def _prior(frame: _Frame, taps: Taps) -> tuple[Array | None, Array]:
    """Rows R and target b so that ``R @ (x, y, 1) - b`` are the residuals of
    the tap on friend 2, whitened by the tap's covariance (a line: by its sigma across the line)."""
    if taps.epipole1 is not None and taps.cov_e1 is not None:
        tap = frame.t1 @ np.append(taps.epipole1, 1.0)
        rows = whitener(taps.cov_e1) @ np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]) / frame.s1
        return rows, rows[:, :2] @ tap[:2]
    if taps.line1 is not None:
        line = linalg.solve(frame.t1.T, taps.line1)  # lines map by the inverse transpose
        scale = np.hypot(line[0], line[1]) * frame.s1 * taps.line_sigma
        return (line / scale)[None, :], np.zeros(1)
    return None, np.zeros(0)


def _pixel_covariance(
    to_pixels_from: Array, point_n: Array, d_point_n: Array, covariance: Array
) -> Array | None:
    """(2, 2) pixel covariance of a homogeneous normalised point with Jacobian (3, P)."""
    point = linalg.solve(to_pixels_from, point_n)
    d_point = linalg.solve(to_pixels_from, d_point_n)
    if abs(point[2]) < _FAR_W * linalg.norm(point):
        return None
    w = point[2]
    dehomogenise = np.array([[1.0, 0.0, -point[0] / w], [0.0, 1.0, -point[1] / w]]) / w
    jacobian = dehomogenise @ d_point
    return jacobian @ covariance @ jacobian.T


def sampson_distances(fundamental: Array, p: Array, q: Array) -> Array:
    """Signed Sampson distances (px) of landmarks to one or many geometries.

    Args:
        fundamental: (3, 3) or (K, 3, 3) F in pixels.
        p, q: (N, 2) landmarks of photo 1 and photo 2.

    Returns:
        (N,) or (K, N) distances.
    """
    ph, qh = homogeneous(p), homogeneous(q)
    if fundamental.ndim == 2:  # one geometry: plain products (einsum's '...' costs more)
        fp, ftq = ph @ fundamental.T, qh @ fundamental
        eps = np.einsum("ni,ni->n", fp, qh)
    else:
        fp = np.einsum("kij,nj->kni", fundamental, ph)
        ftq = np.einsum("kji,nj->kni", fundamental, qh)
        eps = np.einsum("kni,ni->kn", fp, qh)
    g2 = fp[..., 0] ** 2 + fp[..., 1] ** 2 + ftq[..., 0] ** 2 + ftq[..., 1] ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        return eps / np.sqrt(g2)


def whitened_distances(fundamental: Array, taps: Taps) -> Array:
    """Sampson distances in each landmark's own sigmas, for one or many geometries.

    Args:
        fundamental: (3, 3) or (K, 3, 3) F in pixels.
        taps: the landmarks and their covariances.

    Returns:
        (N,) or (K, N) signed distances (unit variance under tap noise).
    """
    ph, qh = homogeneous(taps.p), homogeneous(taps.q)
    fp = np.einsum("...ij,nj->...ni", fundamental, ph)
    ftq = np.einsum("...ji,nj->...ni", fundamental, qh)
    eps = np.einsum("...ni,ni->...n", fp, qh)
    g2 = np.einsum("...ni,nij,...nj->...n", ftq[..., :2], taps.cov_p, ftq[..., :2]) + np.einsum(
        "...ni,nij,...nj->...n", fp[..., :2], taps.cov_q, fp[..., :2]
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        return eps / np.sqrt(g2)
