"""How sure the answer is: the 95 % ellipse of friend 1's position, and its quality.

The ellipse is first-order propagation of the tap noise through the maximum-likelihood fit;
where that is measured to be too optimistic (minimal cases), :mod:`bootstrap` calibrates its
size. Coverage is measured in the test suite and in ``benchmarks/solver.py``.
"""

from __future__ import annotations

import functools
import math
from statistics import NormalDist
from typing import Protocol

import numpy as np

from .. import linalg
from ..projective import Array
from ..result import Quality

LEVEL = 0.95
# Chi-square quantile with 2 degrees of freedom at LEVEL: -2 ln(1 - LEVEL).
CHI2_2D = -2.0 * math.log(1.0 - LEVEL)  # = chi2_quantile(LEVEL, 2)

_STANDARD_NORMAL = NormalDist()

# Points on each ellipse's boundary that a region over two must hold, and a margin for the
# arcs between them.
_BOUNDARY_POINTS = 72
_MARGIN = 1.02
_ANGLES = np.linspace(0.0, 2.0 * math.pi, _BOUNDARY_POINTS, endpoint=False)
_CIRCLE = np.column_stack([np.cos(_ANGLES), np.sin(_ANGLES)])

# Quality bands: the 95 % ellipse's longer semi-axis as a fraction of photo 2's diagonal.
GOOD_FRACTION = 0.03
FAIR_FRACTION = 0.10


class Fitted(Protocol):
    """A fit with a chi-square cost (squared whitened residuals) and its degrees of freedom."""

    @property
    def cost(self) -> float: ...

    @property
    def dof(self) -> int: ...


def consistent(fit: Fitted, probability: float = 0.99) -> bool:
    """Whether the fit's whitened residuals are what tap noise explains (chi-square test)."""
    return fit.dof <= 0 or fit.cost <= chi2_quantile(probability, fit.dof)


@functools.cache
def chi2_quantile(probability: float, dof: int) -> float:
    """Quantile of the chi-square distribution: exact for 1 and 2 degrees of freedom,
    Wilson-Hilferty beyond (within 0.5 % from 3 on)."""
    if dof == 2:
        return -2.0 * math.log(1.0 - probability)
    if dof == 1:
        return _STANDARD_NORMAL.inv_cdf(0.5 + 0.5 * probability) ** 2
    z = _STANDARD_NORMAL.inv_cdf(probability)
    h = 2.0 / (9.0 * dof)
    return dof * (1.0 - h + z * math.sqrt(h)) ** 3


def ellipse(
    centre: Array, covariance: Array
) -> tuple[tuple[float, float], tuple[float, float], float]:
    """(centre, (a, b) semi-axes in px, angle of axis a from the x axis in degrees, y down)."""
    # The eigen-decomposition of a symmetric 2x2 matrix in closed form.
    (xx, xy), (_, yy) = covariance.tolist()
    mean, half_gap = 0.5 * (xx + yy), math.hypot(0.5 * (xx - yy), xy)
    larger = max(mean + half_gap, 0.0)
    # The smaller eigenvalue as the determinant over the larger: mean - half_gap cancels to
    # 0 when the two differ by 16 orders of magnitude (a region 1e5 px long and 1e-3 px
    # wide), which would be drawn as a region of no width, a false certainty. (At most the
    # larger: a circle's two, rounded apart, would swap.)
    smaller = min(max((xx * yy - xy * xy) / larger, 0.0), larger) if larger > 0.0 else 0.0
    angle = math.degrees(0.5 * math.atan2(2.0 * xy, xx - yy)) % 180.0  # the major axis
    a, b = math.sqrt(CHI2_2D * larger), math.sqrt(CHI2_2D * smaller)
    return (float(centre[0]), float(centre[1])), (a, b), angle


def holdable(axes: tuple[float, float]) -> bool:
    """Whether semi-axes (a, b) from :func:`ellipse` make a region a float can hold: some
    width, a finite length (else there is no region: a false certainty, or none at all)."""
    return 0.0 < axes[1] <= axes[0] < math.inf


def contains(centre: Array, covariance: Array, point: Array) -> bool:
    """Whether ``point`` lies inside the LEVEL ellipse of (centre, covariance)."""
    offset = point - centre
    return bool(offset @ linalg.solve(covariance, offset) <= CHI2_2D)


def covering(own: tuple[Array, Array], other: tuple[Array, Array]) -> Array:
    """(2, 2) a covariance about ``own``'s centre whose 95 % ellipse holds both answers'
    95 % ellipses, each given as (centre (2,), covariance (2, 2)): the shape of both
    spreads and the gap between them, scaled to hold every point on the two boundaries.
    For an answer that may be either of two readings: the truth is in one of them."""
    (a, cov_a), (b, cov_b) = own, other
    gap = b - a
    shape = cov_a + cov_b + np.outer(gap, gap) / CHI2_2D
    points = np.vstack([_boundary(a, cov_a), _boundary(b, cov_b)]) - a
    inverse = linalg.inv(shape)
    scale = float(np.einsum("ki,ij,kj->k", points, inverse, points).max()) / CHI2_2D
    return shape * scale * _MARGIN


def _boundary(centre: Array, covariance: Array) -> Array:
    """(K, 2) points on the 95 % ellipse of (centre, covariance)."""
    root = linalg.cholesky2(covariance)
    return centre + math.sqrt(CHI2_2D) * _CIRCLE @ root.T


def quality(semi_major: float | None, diagonal: float) -> Quality:
    """'good', 'fair' or 'poor' from the ellipse's longer semi-axis (None: unbounded)."""
    if semi_major is None or not math.isfinite(semi_major):
        return "poor"
    if semi_major <= GOOD_FRACTION * diagonal:
        return "good"
    if semi_major <= FAIR_FRACTION * diagonal:
        return "fair"
    return "poor"
