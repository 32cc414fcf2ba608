"""The taps as the estimators see them: positions and how precise each one is.

A person taps at whatever zoom they happen to use, so each tap has its own precision: a
(2, 2) covariance in photo pixels squared (``sigma^2 I`` for a round finger). Every fit
weighs each residual by it, so a tap made zoomed in counts for more than one made on the
whole photo.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..linalg import cholesky2, whitener2
from ..projective import Array, Indices


@dataclass(frozen=True)
class Gravity:
    """Which way is down in each photo's camera frame, as its phone measured it at the
    shutter: x right along the photo's rows, y down its columns, z out of the lens.

    Attributes:
        gravity1, gravity2: (3,) unit vectors towards the ground, frames 1 and 2.
        sigma1, sigma2: each reading's standard deviation per axis, radians.
    """

    gravity1: Array
    gravity2: Array
    sigma1: float
    sigma2: float

    @property
    def sigma(self) -> float:
        """The standard deviation of the two readings' disagreement per axis, radians: the
        model ``R g1 = g2`` is tested on it."""
        return math.hypot(self.sigma1, self.sigma2)


@dataclass(frozen=True)
class Heading:
    """Which way each phone's lens looked at the shutter, as its compass measured it: the
    heading of the lens axis's horizontal direction, clockwise from north seen from above.
    Only their difference is used (both phones share a north, magnetic or true), and only
    with both phones' gravity (:class:`Gravity`), which says what is horizontal.

    Attributes:
        heading1, heading2: radians, clockwise from north, photos 1 and 2.
        sigma1, sigma2: each heading's standard deviation, radians.
    """

    heading1: float
    heading2: float
    sigma1: float
    sigma2: float

    @property
    def sigma(self) -> float:
        """The standard deviation of the two headings' difference, radians: the turn about
        the vertical between the phones is measured with it."""
        return math.hypot(self.sigma1, self.sigma2)


@dataclass(frozen=True)
class Taps:
    """Landmarks in both photos and the friends' marks, each with its covariance.

    Attributes:
        p, q: (N, 2) landmarks in photo 1 (friend 1's) and photo 2 (friend 2's), px.
        cov_p, cov_q: (N, 2, 2) their covariances, px^2.
        epipole1: (2,) friend 2 tapped in photo 1, or None; cov_e1: (2, 2) px^2.
        epipole2: (2,) friend 1 tapped in photo 2, or None; cov_e2: (2, 2) px^2.
        line1: (3,) a line through friend 2 in photo 1 (a x + b y + c = 0), or None;
            line_sigma: its standard deviation across the line, px.
        gravity: both phones' gravity at the shutter, or None (:class:`Gravity`).
        heading: both phones' compass headings at the shutter, or None (:class:`Heading`);
            only with ``gravity``.
    """

    p: Array
    q: Array
    cov_p: Array
    cov_q: Array
    epipole1: Array | None = None
    cov_e1: Array | None = None
    epipole2: Array | None = None
    cov_e2: Array | None = None
    line1: Array | None = None
    line_sigma: float = 1.0
    gravity: Gravity | None = None
    heading: Heading | None = None

    @classmethod
    def isotropic(
        cls,
        p: Array,
        q: Array,
        sigma: float,
        *,
        epipole1: Array | None = None,
        epipole2: Array | None = None,
        line1: Array | None = None,
    ) -> Taps:
        """Every tap with the same round precision ``sigma`` px per axis."""
        round_ = sigma**2 * np.eye(2)
        return cls(
            p,
            q,
            np.broadcast_to(round_, (len(p), 2, 2)).copy(),
            np.broadcast_to(round_, (len(q), 2, 2)).copy(),
            epipole1,
            None if epipole1 is None else round_,
            epipole2,
            None if epipole2 is None else round_,
            line1,
            sigma,
        )

    def __len__(self) -> int:
        return len(self.p)

    def subset(self, keep: Indices) -> Taps:
        """The same marks with only the landmarks ``keep`` (indices)."""
        return replace(
            self, p=self.p[keep], q=self.q[keep], cov_p=self.cov_p[keep], cov_q=self.cov_q[keep]
        )

    def without(self, dropped: Sequence[int]) -> Taps:
        """The same marks without the landmarks ``dropped`` (indices); these very taps when
        none is, as in most searches (numpy's set difference alone costs tens of
        microseconds)."""
        if not len(dropped):
            return self
        return self.subset(np.setdiff1d(np.arange(len(self)), dropped))

    def retapped(self, rng: np.random.Generator) -> Taps:
        """The landmarks as the same fingers might tap them again: fresh noise of each
        tap's own covariance (the friends' marks are left as they are)."""
        return replace(
            self, p=_jittered(self.p, self.cov_p, rng), q=_jittered(self.q, self.cov_q, rng)
        )

    @functools.cached_property
    def mark_whiteners(self) -> tuple[Array | None, Array | None]:
        """(2, 2) whiteners of friend 2's and friend 1's marks (:func:`whitener`; None where
        not marked), once for every model of these taps (the fit's and the bootstrap's)."""
        return (
            None if self.cov_e1 is None else whitener(self.cov_e1),
            None if self.cov_e2 is None else whitener(self.cov_e2),
        )

    @property
    def typical_sigma(self) -> float:
        """A single px figure for the landmarks' precision: the root-mean-square sigma (the
        friend mark's with no landmark)."""
        variances = np.concatenate(
            [self.cov_p.trace(axis1=1, axis2=2), self.cov_q.trace(axis1=1, axis2=2)]
        )
        if not len(variances) and self.cov_e1 is not None:
            variances = np.array([np.trace(self.cov_e1)])
        if not len(variances):
            return math.nan
        # The mean as numpy's mean takes it (the same sum over the same count), without its
        # Python-level wrapper: this runs in every solve.
        return math.sqrt(float(np.add.reduce(variances)) / len(variances) / 2.0)


def _jittered(points: Array, covariances: Array, rng: np.random.Generator) -> Array:
    factors = cholesky2(covariances)
    return points + np.einsum("nij,nj->ni", factors, rng.normal(size=points.shape))


def whitener(covariance: Array) -> Array:
    """(2, 2) or (N, 2, 2) W with ``W^T W = covariance^-1``: W (x - mean) has unit variance."""
    return whitener2(covariance)
