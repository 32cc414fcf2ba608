"""Which landmark was mis-tapped? Consensus over minimal sets of five landmarks.

Run only when the taps disagree more than tap noise explains (the fit's chi-square test
fails). With the buddy's tap, every subset of five landmarks (all of them up to nine
landmarks, a fixed random sample beyond) proposes a geometry by the linear five-point route,
and the one most landmarks agree with (truncated least squares, MSAC) defines the inliers;
without it OpenCV's USAC does the same over sets of seven. The inliers are refitted. The
rest are named as suspects only if the refit on the inliers passes the chi-square test with
at least one degree of freedom to spare: with fewer landmarks no single culprit can be told
from a bad scene, and the caller says so instead.
"""

from __future__ import annotations

import math
from itertools import combinations

import cv2
import numpy as np

from .. import words
from ..errors import ErrorCode, SolverError
from ..minimal.five_point_linear import fundamental_with_epipole
from ..projective import (
    Array,
    hartley_normaliser,
    homogeneous,
    orthogonal_complement,
    transform,
    unit,
)
from .epipolar_fit import EpipolarFit, fit_epipolar, sampson_distances
from .uncertainty import chi2_quantile

MAX_HYPOTHESES = 126
# Hypotheses come from noisy minimal sets, so inliers sit further from them than from the
# final fit: a loose threshold to form the consensus, a tight one to name suspects.
CONSENSUS_SIGMAS = 4.0
_SEED = 5


def consistent(fit: EpipolarFit, sigma: float, probability: float = 0.99) -> bool:
    """Whether the fit's residuals are what tap noise of ``sigma`` explains."""
    return fit.dof <= 0 or fit.cost / sigma**2 <= chi2_quantile(probability, fit.dof)


def find_mistaps(
    p: Array, q: Array, sigma: float, *, epipole1_tap: Array | None = None
) -> tuple[list[int], EpipolarFit] | None:
    """Suspect landmarks and the fit without them, or None if no subset explains the taps.

    Args:
        p, q: (N, 2) landmarks; N >= 7 with the buddy's tap, N >= 9 without.
        sigma: tap noise, px.
        epipole1_tap: (2,) the buddy's tap in photo 1, or None (then OpenCV's USAC finds
            the consensus over 7-landmark sets).
    """
    threshold = CONSENSUS_SIGMAS * sigma
    if epipole1_tap is not None:
        hypotheses = _hypotheses(np.append(epipole1_tap, 1.0), p, q, _subsets(len(p)))
        distances = np.abs(sampson_distances(hypotheses, p, q))
        distances[~np.isfinite(distances)] = np.inf
        scores = np.minimum(distances, threshold) ** 2
        inliers = distances[int(np.argmin(scores.sum(axis=1)))] <= threshold
    else:
        _, mask = cv2.findFundamentalMat(p, q, cv2.USAC_ACCURATE, threshold, 0.999, 10_000)
        if mask is None:
            return None
        inliers = mask.ravel().astype(bool)
    for _ in range(2):  # refit, then re-sort landmarks against the refit once
        if inliers.sum() < _MIN_INLIERS[epipole1_tap is None]:
            return None
        fit = refit(p[inliers], q[inliers], sigma, epipole1_tap)
        inliers = np.abs(sampson_distances(fit.fundamental, p, q)) <= _suspect_threshold(sigma)
    if (
        inliers.sum() < _MIN_INLIERS[epipole1_tap is None]
        or inliers.all()
        or not consistent(fit, sigma)
    ):
        return None
    return [int(i) for i in np.flatnonzero(~inliers)], fit


def refit(p: Array, q: Array, sigma: float, epipole1_tap: Array | None) -> EpipolarFit:
    """Linear start (five-point route with the tap, eight-point without) and ML refinement."""
    if epipole1_tap is not None:
        start = fundamental_with_epipole(np.append(epipole1_tap, 1.0), p, q)
    else:
        found, _ = cv2.findFundamentalMat(p, q, cv2.FM_8POINT)
        start = np.asarray(found, dtype=np.float64)
        if found is None or start.shape != (3, 3):
            raise SolverError(
                ErrorCode.DEGENERATE_CONFIGURATION,
                words.GEOMETRY_UNDETERMINED,
            )
    return fit_epipolar(p, q, start, sigma=sigma, epipole1_tap=epipole1_tap)


# With the buddy's tap five landmarks fix the geometry, without it seven (eight for a
# unique linear start): one more is needed to check a consensus.
_MIN_INLIERS = {False: 6, True: 9}


def _suspect_threshold(sigma: float) -> float:
    """A landmark this far (px) from the refit is not tap noise (two-sided p < 0.001)."""
    return math.sqrt(chi2_quantile(0.999, 1)) * sigma


def _subsets(n: int) -> Array:
    every = math.comb(n, 5)
    if every <= MAX_HYPOTHESES:
        return np.array(list(combinations(range(n), 5)))
    rng = np.random.default_rng(_SEED)
    return np.array([np.sort(rng.choice(n, 5, replace=False)) for _ in range(MAX_HYPOTHESES)])


def _hypotheses(e1: Array, p: Array, q: Array, subsets: Array) -> Array:
    """(K, 3, 3) pixel F of each five-landmark subset (linear route of paper 3.2, batched)."""
    t1, t2 = hartley_normaliser(p), hartley_normaliser(q)
    basis = orthogonal_complement(unit(t1 @ e1))
    along = transform(t1, homogeneous(p)) @ basis
    q_n = transform(t2, homogeneous(q))
    rows = np.hstack([along[:, :1] * q_n, along[:, 1:] * q_n])  # (N, 6)
    _, _, vt = np.linalg.svd(rows[subsets])  # (K, 6, 6)
    columns = vt[:, -1, :].reshape(-1, 2, 3).transpose(0, 2, 1)  # (K, 3, 2)
    return t2.T @ (columns @ basis.T) @ t1
