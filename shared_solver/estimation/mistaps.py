"""Which landmark was mis-tapped? Consensus over minimal sets of five landmarks.

Run only when the taps disagree more than tap noise explains (the fit's chi-square test
fails). With friend 2's tap, every subset of five landmarks (all of them up to nine
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

from ..errors import Reason
from ..minimal.five_point_linear import fundamental_with_epipole
from ..projective import (
    Array,
    hartley_normaliser,
    homogeneous,
    orthogonal_complement,
    transform,
    unit,
)
from ..refusal import SolverError
from .epipolar_fit import EpipolarFit, fit_epipolar, whitened_distances
from .taps import Taps
from .uncertainty import chi2_quantile, consistent

MAX_HYPOTHESES = 126
# Hypotheses come from noisy minimal sets, so inliers sit further from them than from the
# final fit: a loose threshold (in sigmas) to form the consensus, a tight one to name suspects.
CONSENSUS_SIGMAS = 4.0
_SEED = 5


def find_mistaps(taps: Taps, *, use_friend2: bool) -> tuple[list[int], EpipolarFit] | None:
    """Suspect landmarks and the fit without them, or None if no subset explains the taps.

    Args:
        taps: landmarks (N >= 7 with friend 2's tap, N >= 9 without) with covariances.
        use_friend2: whether friend 2's tap takes part (False: OpenCV's USAC finds the
            consensus over 7-landmark sets, with a threshold of the typical tap's sigma).
    """
    if use_friend2:
        assert taps.epipole1 is not None
        hypotheses = _hypotheses(np.append(taps.epipole1, 1.0), taps.p, taps.q, _subsets(len(taps)))
        distances = np.abs(whitened_distances(hypotheses, taps))
        distances[~np.isfinite(distances)] = np.inf
        scores = np.minimum(distances, CONSENSUS_SIGMAS) ** 2
        inliers = distances[int(np.argmin(scores.sum(axis=1)))] <= CONSENSUS_SIGMAS
    else:
        threshold = CONSENSUS_SIGMAS * taps.typical_sigma
        _, mask = cv2.findFundamentalMat(
            taps.p, taps.q, cv2.USAC_ACCURATE, threshold, 0.999, 10_000
        )
        if mask is None:
            return None
        inliers = mask.ravel().astype(bool)
    minimum = _MIN_INLIERS[use_friend2]
    for _ in range(2):  # refit, then re-sort landmarks against the refit once
        if inliers.sum() < minimum:
            return None
        fit = refit(taps.subset(np.flatnonzero(inliers)), use_friend2=use_friend2)
        inliers = np.abs(whitened_distances(fit.fundamental, taps)) <= SUSPECT_SIGMAS
    if inliers.sum() < minimum or inliers.all() or not consistent(fit):
        return None
    return [int(i) for i in np.flatnonzero(~inliers)], fit


def refit(taps: Taps, *, use_friend2: bool) -> EpipolarFit:
    """Linear start (five-point route with the tap, eight-point without) and ML refinement."""
    if use_friend2:
        assert taps.epipole1 is not None
        start = fundamental_with_epipole(np.append(taps.epipole1, 1.0), taps.p, taps.q)
    else:
        found, _ = cv2.findFundamentalMat(taps.p, taps.q, cv2.FM_8POINT)
        start = np.asarray(found, dtype=np.float64)
        if found is None or start.shape != (3, 3):
            raise SolverError(Reason.GEOMETRY_UNDETERMINED)
    return fit_epipolar(taps, start, use_friend2=use_friend2)


# With friend 2's tap five landmarks fix the geometry, without it seven (eight for a
# unique linear start): one more is needed to check a consensus.
_MIN_INLIERS = {True: 6, False: 9}
# A landmark this far (in its sigmas) from the refit is not tap noise (two-sided p < 0.001).
SUSPECT_SIGMAS = math.sqrt(chi2_quantile(0.999, 1))


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
