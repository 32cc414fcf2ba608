"""Which landmark was mis-tapped, with the camera model? Consensus over sets of three.

With both cameras modelled, three landmarks and friend 2 fix the geometry
(:mod:`...minimal.epipole_and_three`), so a consensus needs only four landmarks and one more
to name a culprit: from five landmarks on, where the projective search needs seven. Run
only when the camera-aware fit fails its chi-square test: every set of three landmarks (a
fixed random sample of them for many landmarks) proposes its poses, the one most landmarks
agree with (truncated least squares, MSAC) defines the inliers, and they are refitted. The
rest are named only if that refit passes the chi-square test with a degree of freedom to
spare; otherwise the caller says the marks disagree.
"""

from __future__ import annotations

import numpy as np

from ..mistaps import CONSENSUS_SIGMAS, SUSPECT_SIGMAS
from ..uncertainty import consistent
from .fit import PinholeFit, fit_pinhole
from .model import PinholeModel
from .starts import behind, combinations_of, exact_poses

# Three landmarks fix the pose, one more checks it: a consensus needs four.
_MIN_INLIERS = 4
# Sets of three tried at most (all of them up to 6 landmarks): with one mis-tap among N,
# a set is clean with probability (N - 3) / N, so 20 leave no chance of missing one.
MAX_TRIPLES = 20
_SEED = 11


def find_pinhole_mistaps(model: PinholeModel) -> tuple[list[int], PinholeFit] | None:
    """Suspect landmarks and the camera-aware fit without them, or None if no subset
    explains the taps.

    Args:
        model: every tap (friend 2 marked as a point, N >= 5 landmarks) and the priors.
    """
    taps = model.taps
    count = len(taps)
    if count < _MIN_INLIERS + 1:
        return None
    triples = combinations_of(count, 3)
    if len(triples) > MAX_TRIPLES:
        rng = np.random.default_rng(_SEED)
        triples = triples[rng.choice(len(triples), MAX_TRIPLES, replace=False)]
    poses = exact_poses(model, [tuple(int(i) for i in t) for t in triples])
    if poses is None:
        return None
    distances = np.abs(model.offsets(poses)[:, :count])
    truncated = np.minimum(distances, CONSENSUS_SIGMAS) ** 2
    # A pose that puts landmarks behind a camera is charged a full outlier for each.
    costs = truncated.sum(axis=1) + CONSENSUS_SIGMAS**2 * behind(poses, model)
    best = int(np.argmin(costs))
    inliers = distances[best] <= CONSENSUS_SIGMAS
    start = poses.member(best)
    for _ in range(2):  # refit, then re-sort the landmarks against the refit once
        if inliers.sum() < _MIN_INLIERS:
            return None
        fit = fit_pinhole(PinholeModel(taps.subset(np.flatnonzero(inliers)), model.priors), start)
        start = fit.pose
        inliers = np.abs(model.offsets(fit.pose)[0, :count]) <= SUSPECT_SIGMAS
    if inliers.sum() < _MIN_INLIERS or inliers.all() or not fit.usable or not consistent(fit):
        return None
    return [int(i) for i in np.flatnonzero(~inliers)], fit
