"""Where the pinhole fit starts: every pose the exact solvers allow, ranked by the taps.

The fit (:mod:`.fit`) is local, so it starts from the exact solutions of a few
minimal subsets at the priors' focal lengths: three landmarks and friend 2
(:mod:`...minimal.epipole_and_three`), one landmark and both friends
(:mod:`...minimal.both_and_one`), one landmark, friend 2 and both phones' gravity
(:mod:`...minimal.gravity_and_one`), or, when friend 2 was not marked as a point, the
projective solutions turned into poses (the essential matrix of OpenCV's decomposition).
Each candidate is scored on every tap: squared whitened residuals (each capped, so one
mis-tap cannot veto the right pose) and the landmarks it would put behind a camera.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from itertools import combinations

import cv2
import numpy as np

from ... import linalg
from ...minimal.both_and_one import rotations_from_both
from ...minimal.epipole_and_three import rotations_from_three
from ...minimal.gravity_and_one import rotations_from_gravity
from ...projective import Array, Indices
from ..camera import FocalPrior
from ..taps import Taps
from .model import PinholeModel
from .pose import Poses

# A residual beyond this many sigmas counts as this many: an outlier, not a veto.
_CAP_SIGMAS = 6.0
# Each landmark behind a camera costs as much as a capped residual.
_BEHIND_PENALTY = _CAP_SIGMAS**2
# Minimal subsets used: one landmark (both friends marked); the two best-spread sets of
# three (up to 8 rotations each). One changed no answer on main-camera phone scenes, but on
# photos zoomed 5x it led every start into a basin 1260 px off while a better one fit (3 in
# 300 searches; the second set found it every time). A mis-tap in them is the mis-tap
# search's to find (mistaps.py). When tap noise leaves a set of three with no real
# pose, the next is tried, up to _SUBSETS_TRIED.
_SUBSETS = 1
_TRIPLES = 2
_SUBSETS_TRIED = 5
# With both phones' gravity, one landmark and friend 2's mark give up to two poses: those
# of this many landmarks, the farthest from friend 2's mark, are started from too.
_GRAVITY_SUBSETS = 2
# Two candidates that put friend 1 closer than this (radians apart, about 60 px at a phone's
# focal length) are the same start: different subsets of noisy taps give slightly different
# poses of one basin.
_SAME_DIRECTION = 0.02
# When no fit from those starts agrees with the taps (about 1 in 1000 honest taps on phone
# scenes: the best-spread set of three can lead every start into a wrong basin), the search
# widens: more sets of three, each also read at focal lengths from the ultra-wide to a 5x
# zoom on either photo, since a start at the priors' median can miss a zoomed photo's basin.
_WIDER_SUBSETS = 6
_WIDER_ZOOMS = ((1.0, 1.0), (1.0, 2.0), (2.0, 1.0), (1.0, 4.0), (4.0, 1.0), (0.5, 0.5), (2.0, 2.0))


def marked_starts(model: PinholeModel) -> list[tuple[float, Poses]]:
    """Scored candidate poses when friend 2 is marked as a point (and maybe friend 1).

    Returns:
        ``(score, pose)`` pairs, best (lowest) first, one per distinct direction of friend 1.
    """
    taps = model.taps
    singles = _spread_indices(taps, 1, _SUBSETS) if taps.epipole2 is not None else []
    triples = _spread_indices(taps, 3, _SUBSETS_TRIED) if len(taps) >= 3 else []
    # Gravity's own poses only where no set of three gives any: from three landmarks they
    # changed no answer (the same 300 phone searches to the pixel) and tripled the time.
    levelled = gravity_poses(model, _GRAVITY_SUBSETS) if len(taps) < 3 else None
    # The best-spread sets of three, skipping those that noise leaves with no real pose.
    found: list[Poses] = []
    for triple in triples:
        poses = exact_poses(model, [triple], singles)
        if poses is not None:
            found.append(poses)
            if len(found) == _TRIPLES:
                break
    if found:
        return _ranked(model, *found, levelled)
    return _ranked(model, exact_poses(model, [], singles), levelled)


def wider_marked_starts(model: PinholeModel) -> list[tuple[float, Poses]]:
    """More candidate poses (friend 2 marked as a point), for when none of
    :func:`marked_starts` refines to a fit that agrees with the taps: more sets of three,
    each at several focal lengths of either photo (``_WIDER_ZOOMS``). Best first, one per
    distinct direction of friend 1."""
    taps = model.taps
    singles = _spread_indices(taps, 1, _WIDER_SUBSETS) if taps.epipole2 is not None else []
    triples = _spread_indices(taps, 3, _WIDER_SUBSETS) if len(taps) >= 3 else []
    return _ranked(
        model,
        *(exact_poses(model, triples, singles, zoom=zoom) for zoom in _WIDER_ZOOMS),
        *(gravity_poses(model, _WIDER_SUBSETS, zoom=zoom) for zoom in _WIDER_ZOOMS),
    )


def exact_poses(
    model: PinholeModel,
    triples: Sequence[Sequence[int]],
    singles: Sequence[Sequence[int]] = (),
    *,
    friend2_places: Array | None = None,
    zoom: tuple[float, float] = (1.0, 1.0),
) -> Poses | None:
    """Every pose the minimal solvers give at the priors' focal lengths: three landmarks and
    friend 2 for each of ``triples``, one landmark and both friends for each of
    ``singles`` (landmark indices). None when they give none.

    ``friend2_places``: (B, 2) pixels of photo 1 to try as friend 2 (a line through friend 2
    gives candidates); by default friend 2's tap. ``zoom``: the focal lengths used, as
    multiples of the priors' medians (photo 1, photo 2).
    """
    taps, priors = model.taps, model.priors
    if friend2_places is None:
        assert taps.epipole1 is not None
        friend2_places = taps.epipole1[None]
    focal1 = np.array([priors[0].focal_px * zoom[0]])
    focal2 = np.array([priors[1].focal_px * zoom[1]])
    centred1, centred2 = model.centred_taps
    rays1 = _rays_at(centred1, focal1)[0]
    rays2 = _rays_at(centred2, focal2)[0]
    rotations: list[Array] = []
    directions: list[Array] = []
    for ray in _rays_at(friend2_places - model.centres[0], focal1)[0]:
        friend2 = _unit(ray)
        found: list[Array] = []
        if taps.epipole2 is not None:
            friend1 = _unit(_rays_at(taps.epipole2[None] - model.centres[1], focal2)[0, 0])
            for (i,) in singles:
                found += rotations_from_both(friend2, friend1, rays1[i], rays2[i])
        for triple in triples:
            index = list(triple)
            found += rotations_from_three(friend2, rays1[index], rays2[index])
        rotations += found
        directions += [friend2] * len(found)
    if not rotations:
        return None
    return _poses(model, np.array(rotations), np.array(directions), zoom)


def gravity_poses(
    model: PinholeModel, count: int, *, zoom: tuple[float, float] = (1.0, 1.0)
) -> Poses | None:
    """Every pose of one landmark, friend 2's mark and both phones' gravity
    (:mod:`...minimal.gravity_and_one`) for each of the ``count`` landmarks farthest from
    friend 2's mark, at the priors' focal lengths times ``zoom``; None without gravity."""
    taps, priors, gravity = model.taps, model.priors, model.taps.gravity
    if gravity is None or taps.epipole1 is None or not len(taps):
        return None
    focal1 = np.array([priors[0].focal_px * zoom[0]])
    focal2 = np.array([priors[1].focal_px * zoom[1]])
    centred1, centred2 = model.centred_taps
    rays1 = _rays_at(centred1, focal1)[0]
    rays2 = _rays_at(centred2, focal2)[0]
    friend2 = _unit(_rays_at(taps.epipole1[None] - model.centres[0], focal1)[0, 0])
    # Far from friend 2's mark, a landmark's epipolar plane is well fixed by its two rays.
    order = np.argsort(-np.linalg.norm(taps.p - taps.epipole1, axis=1), kind="stable")
    rotations: list[Array] = []
    for i in order[:count].tolist():
        rotations += rotations_from_gravity(
            friend2, gravity.gravity1, gravity.gravity2, rays1[i], rays2[i]
        )
    if not rotations:
        return None
    return _poses(model, np.array(rotations), _repeated(friend2, len(rotations)), zoom)


def unmarked_starts(
    model: PinholeModel, fundamentals: list[Array], friend2_places: Array
) -> list[tuple[float, Poses]]:
    """Scored candidate poses when friend 2 was not marked as a point: the poses of the
    projective solutions ``fundamentals``, and the three-landmark solver with friend 2 at
    each of ``friend2_places`` (B, 2) pixels (the solutions' own, and places along a line
    through friend 2 if one was drawn). With noisy taps a projective solution can be far
    from any pair of phone cameras while it puts friend 2 near the right place."""
    found = [fundamental_poses(model, fundamentals)]
    for triple in _spread_indices(model.taps, 3, _SUBSETS_TRIED) if len(friend2_places) else []:
        poses = exact_poses(model, [triple], friend2_places=friend2_places)
        if poses is not None:
            found.append(poses)
            break
    return _ranked(model, *found)


def fundamental_starts(model: PinholeModel, fundamentals: list[Array]) -> list[tuple[float, Poses]]:
    """Scored candidate poses from projective solutions (3, 3) F in pixels."""
    return _ranked(model, fundamental_poses(model, fundamentals))


def fundamental_poses(model: PinholeModel, fundamentals: list[Array]) -> Poses | None:
    """Each F read at the priors' focal lengths as an essential matrix, and each of its four
    decompositions (Hartley & Zisserman 9.6.2) as a pose; None when there is no F."""
    k1, k2 = (_intrinsics(prior) for prior in model.priors)
    rotations: list[Array] = []
    baselines: list[Array] = []
    for fundamental in fundamentals:
        first, second, translation = cv2.decomposeEssentialMat(k2.T @ fundamental @ k1)
        for rotation in (np.asarray(first, dtype=np.float64), np.asarray(second, dtype=np.float64)):
            # t is friend 1's centre in frame 2, along -R b1: b1 = -R^T t, either sign.
            along = rotation.T @ np.ravel(translation)
            rotations += [rotation, rotation]
            baselines += [-along, along]
    if not rotations:
        return None
    units = np.array(baselines)
    units /= np.sqrt(np.einsum("ki,ki->k", units, units))[:, None]
    return _poses(model, np.array(rotations), units)


def _poses(
    model: PinholeModel, rotations: Array, baselines: Array, zoom: tuple[float, float] = (1.0, 1.0)
) -> Poses:
    """(K, 3, 3) rotations and (K, 3) unit baselines (friend 2's direction) as poses at the
    priors' focal lengths times ``zoom``; photo 1's reference focal length is its prior's."""
    priors = model.priors
    log_focals = np.array([priors[0].log_focal, priors[1].log_focal]) + np.log(zoom)
    directions = np.array(baselines, dtype=np.float64)
    # Friend 2's direction is kept as the reference focal length sees it: u ~ diag(z, z, 1) b1.
    directions[:, :2] *= zoom[0]
    directions /= np.sqrt(np.einsum("ki,ki->k", directions, directions))[:, None]
    return Poses(
        rotations,
        np.ascontiguousarray(directions),
        _repeated(log_focals, len(rotations)),
        float(priors[0].log_focal),
    )


def score(model: PinholeModel, poses: Poses) -> Array:
    """(K,) how badly each pose fits every tap: squared whitened residuals, each capped so one
    mis-tap cannot veto the right pose, plus a capped residual per landmark it puts behind
    a camera."""
    r = model.offsets(poses)
    return np.minimum(r * r, _CAP_SIGMAS**2).sum(axis=1) + _BEHIND_PENALTY * behind(poses, model)


def _ranked(model: PinholeModel, *batches: Poses | None) -> list[tuple[float, Poses]]:
    """Candidate poses scored on every tap, best first, one per distinct direction of friend 1."""
    present = [batch for batch in batches if batch is not None]
    if not present:
        return []
    poses = Poses(
        np.concatenate([batch.rotation for batch in present]),
        np.concatenate([batch.friend2 for batch in present]),
        np.concatenate([batch.log_focals for batch in present]),
        present[0].reference,
    )
    scores = score(model, poses)
    friend1_directions = -np.einsum("kij,kj->ki", poses.rotation, poses.baseline)
    friend1_directions /= np.sqrt(np.einsum("ki,ki->k", friend1_directions, friend1_directions))[
        :, None
    ]
    same = (friend1_directions @ friend1_directions.T >= math.cos(_SAME_DIRECTION)).tolist()
    kept: list[int] = []
    for k in np.argsort(scores, kind="stable").tolist():
        if not any(same[k][other] for other in kept):
            kept.append(k)
    return [(float(scores[k]), poses.member(k)) for k in kept]


def behind(poses: Poses, model: PinholeModel) -> Array:
    """(K,) how many landmarks each pose puts behind friend 1's or friend 2's camera.

    The landmark is where the two rays pass closest (midpoint triangulation, with the
    cameras a unit apart); a landmark beyond friend 2 along the baseline has no sign.
    """
    focals = np.exp(poses.log_focals)
    centred1, centred2 = model.centred_taps
    rays1 = _rays_at(centred1, focals[:, 0])  # (K, N, 3) frame 1
    rays2 = _rays_at(centred2, focals[:, 1])  # frame 2
    back2 = np.einsum("kji,knj->kni", poses.rotation, rays2)  # in frame 1
    baseline = poses.baseline[:, None, :]  # camera 2 at b1 in frame 1
    # Solve a r1 - b r2' = b1 in least squares: the depths along each ray.
    a11 = np.einsum("kni,kni->kn", rays1, rays1)
    a12 = -np.einsum("kni,kni->kn", rays1, back2)
    a22 = np.einsum("kni,kni->kn", back2, back2)
    c1 = np.einsum("kni,kni->kn", rays1, baseline)
    c2 = -np.einsum("kni,kni->kn", back2, baseline)
    det = a11 * a22 - a12 * a12
    with np.errstate(divide="ignore", invalid="ignore"):
        depth1 = (a22 * c1 - a12 * c2) / det
        depth2 = (a11 * c2 - a12 * c1) / det
    return ((depth1 <= 0) | (depth2 <= 0)).sum(axis=1)


def _spread_indices(taps: Taps, size: int, count: int) -> list[tuple[int, ...]]:
    """Up to ``count`` subsets of ``size`` landmarks, the best spread in both photos first.

    Spread: the smaller of the two photos' triangle areas (for one landmark, its distance
    from the friends' marks), so no subset is chosen for one good photo alone.
    """
    subsets = combinations_of(len(taps), size)
    if len(subsets) <= 1:
        return [tuple(int(i) for i in subset) for subset in subsets]
    if size == 1:
        assert taps.epipole1 is not None
        assert taps.epipole2 is not None
        spread = np.minimum(
            np.linalg.norm(taps.p - taps.epipole1, axis=1),
            np.linalg.norm(taps.q - taps.epipole2, axis=1),
        )
    else:
        spread = np.minimum(_areas(taps.p[subsets]), _areas(taps.q[subsets]))
    best = np.argsort(-spread, kind="stable")[:count]
    return [tuple(int(i) for i in subsets[k]) for k in best]


@functools.cache
def combinations_of(count: int, size: int) -> Indices:
    """(C, size) every subset of ``size`` of ``count`` landmarks, in lexicographic order."""
    return np.array(list(combinations(range(count), size)), dtype=np.intp).reshape(-1, size)


def _areas(triangles: Array) -> Array:
    """(C,) twice the area of triangles (C, 3, 2)."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    return np.abs(
        (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    )


def _rays_at(centred: Array, focals: Array) -> Array:
    """(K, N, 3) rays of pixels (N, 2), given from the principal point, for K focal
    lengths."""
    rays = np.ones((len(focals), len(centred), 3))
    rays[:, :, :2] = centred[None] / focals[:, None, None]
    return rays


def _repeated(row: Array, count: int) -> Array:
    """(count, n) copies of a row (n,) (``np.tile`` costs several times as much)."""
    rows = np.empty((count, len(row)))
    rows[:] = row
    return rows


def _intrinsics(prior: FocalPrior) -> Array:
    (x, y), f = prior.centre, prior.focal_px
    return np.array([[f, 0.0, x], [0.0, f, y], [0.0, 0.0, 1.0]])


def _unit(vector: Array) -> Array:
    return vector / linalg.norm(vector)
