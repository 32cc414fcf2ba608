"""One rendered hall, searched as the app would search it.

Friend 1 marks friend 2 and both tap 5 landmarks (3 px of noise each, the server's
``tap_sigma``); ``solve`` answers with phone cameras. Then, for other landmarks (up to 4 of
each kind of surface), tapped with the same noise in one photo and not yet in the other,
in both directions:

- the band, and how far the true landmark is from its centre line;
- the search along it and back (``search_band``, ``search_back``), timed as ``suggest``
  spends it (the search back only for a match that may be offered);
- the tap check of a right tap (the truth, tapped) and of two wrong ones: another
  landmark's spot, and the truth moved 2-10 % of the diagonal in a random direction;
- with ``compare``, the same search on grey photos, and SIFT keypoints matched in the
  band (:mod:`.sift`).

Spots that one photo shows and the other does not are searched for too: any suggestion
there is wrong. Every random draw comes from the scene's own seed, so a scene is the same
whichever others run with it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import cv2
import numpy as np

from shared_solver import SolverError, SolveResult, solve
from shared_solver.matching import Epipolar, epipolar_band
from shared_solver.matching.band import Band
from shared_solver.matching.polar import Image
from shared_solver.matching.suggestion import (
    RULES,
    Evidence,
    LandmarkSearch,
    Rules,
    check_back,
    gather,
    leads,
    offerable,
    stands_out,
)
from shared_solver.projective import Array, Indices
from testbed.venue import RenderedPair, rendered_pair

from .sift import Features, sift_match

SEED = 20261125
STREAMS = {"calibration": 1, "evaluation": 2}
SIGMA = 3.0  # px per axis: backend/settings.py tap_sigma
USED = 5  # landmarks tapped in both photos before the answer
PER_KIND = 4  # landmarks searched per kind of surface per scene
ABSENT = 6  # spots of one photo only searched per scene and direction
WRONG_OFFSET = (0.02, 0.10)  # a wrong tap's distance from the truth, fraction of the diagonal
ALSO_USED = (3, 8)  # other numbers of landmarks whose bands are checked (no image work)
TAP = SIGMA**2 * np.eye(2)
# The search before it had two views: the patch as read alone; its rule then: a score of 0.7
# and a lead of 0.05 (no other view, no context), the search back landing within 1 % of the tap.
BEFORE = Rules(
    min_score=0.7, min_margin=0.05, views=("as read",), max_across=math.inf, context_radius=0
)


@dataclass(frozen=True)
class Timed:
    """Evidence for one search and what ``suggest`` spends on it (wall and CPU seconds)."""

    evidence: Evidence | None
    seconds: float
    cpu: float


@dataclass(frozen=True)
class Searched:
    """One landmark tapped in photo A and looked for in photo B.

    Attributes:
        scene: the scene's index; direction: 1 if tapped in photo 1 (found in photo 2),
            2 the other way; kind: what it lies on.
        offset: the true landmark's distance from the band's centre line in standard
            deviations of the line there (NaN when the band misses photo B).
        half_width: the band's half-width at the truth, px; length: its length, px.
        colour: the search in the stored (colour) photos; grey: the same on grey photos
            (with ``compare``).
        truth: the true landmark in B; diagonal: B's diagonal, px.
        sift: SIFT's prediction and support (with ``compare``).
        right, swapped, moved: tap checks, in standard deviations: the truth tapped,
            another landmark's spot tapped, the truth moved 2-10 % of the diagonal.
    """

    scene: int
    direction: int
    kind: str
    offset: float
    half_width: float
    length: float
    colour: Timed | None
    grey: Timed | None
    truth: Array
    diagonal: float
    sift: tuple[Array | None, int] | None
    right: float
    swapped: float
    moved: float

    def error(self, timed: Timed | None) -> float:
        """The match's distance from the truth, fraction of the diagonal (NaN: none)."""
        return miss(timed, self.truth, self.diagonal)


def miss(timed: Timed | None, truth: Array, diagonal: float) -> float:
    """The best match's distance from ``truth``, fraction of the ``diagonal`` (NaN: none)."""
    if timed is None or timed.evidence is None:
        return math.nan
    return float(np.hypot(*(timed.evidence.match.point - truth))) / diagonal


@dataclass(frozen=True)
class Absent:
    """A spot photo A shows and photo B does not, looked for in B (``band``: whether its
    band crosses photo B at all)."""

    scene: int
    direction: int
    band: bool
    colour: Timed | None


@dataclass(frozen=True)
class SceneRun:
    """Everything measured on one scene (``answered`` False: too few landmarks, or no
    answer with an uncertainty of F)."""

    index: int
    stream: str
    landmarks: int
    answered: bool
    method: str
    searched: list[Searched]
    absent: list[Absent]
    band_offsets: dict[int, list[float]]  # landmarks used -> offsets of the others (sd)
    render_seconds: float
    sift_seconds: list[float]  # SIFT on each whole photo (with ``compare``)


@dataclass(frozen=True)
class _Direction:
    """What one direction of search needs: A is where the landmarks were tapped."""

    pair: RenderedPair
    index: int
    direction: int
    epipolar: Epipolar
    photo_a: Image
    photo_b: Image
    taps_a: Array
    truths_b: Array
    size_b: tuple[int, int]
    grey: tuple[Image, Image] | None
    features: tuple[Features, Features] | None


def scene_seed(stream: str, index: int) -> tuple[int, int, int]:
    return (SEED, STREAMS[stream], index)


def run_scene(stream: str, index: int, *, compare: bool = False) -> SceneRun:
    """Render scene ``index`` of ``stream`` and measure it (module docstring)."""
    started = time.perf_counter()
    pair = rendered_pair(scene_seed(stream, index))
    render_seconds = time.perf_counter() - started
    rng = np.random.default_rng((*scene_seed(stream, index), 1))
    scene = pair.scene
    count = len(scene.points)
    empty = SceneRun(index, stream, count, False, "", [], [], {}, render_seconds, [])
    if count < USED + 2:
        return empty
    taps1 = scene.landmarks1 + rng.normal(0.0, SIGMA, (count, 2))
    taps2 = scene.landmarks2 + rng.normal(0.0, SIGMA, (count, 2))
    friend2 = scene.epipole1 + rng.normal(0.0, SIGMA, 2)
    order = rng.permutation(count)
    used, rest = order[:USED], order[USED:]
    result = answer(pair, taps1[used], taps2[used], friend2)
    if result is None:
        return empty
    tested = _by_kind(pair, rest)
    grey = features = None
    sift_seconds: list[float] = []
    if compare:
        grey = tuple(_grey(photo) for photo in (pair.photo1, pair.photo2))
        computed = []
        for photo in (pair.photo1, pair.photo2):
            start = time.perf_counter()
            computed.append(Features.of(photo))
            sift_seconds.append(time.perf_counter() - start)
        features = (computed[0], computed[1])
    searched: list[Searched] = []
    absent: list[Absent] = []
    for direction in (1, 2):
        epipolar = Epipolar.from_result(
            result, tapped_in=direction, landmarks1=taps1[used], landmarks2=taps2[used]
        )
        assert epipolar is not None
        first = direction == 1
        context = _Direction(
            pair,
            index,
            direction,
            epipolar,
            pair.photo1 if first else pair.photo2,
            pair.photo2 if first else pair.photo1,
            taps1 if first else taps2,
            scene.landmarks2 if first else scene.landmarks1,
            scene.image_size2 if first else scene.image_size1,
            None if grey is None else (grey[0], grey[1]) if first else (grey[1], grey[0]),
            None if features is None else features if first else (features[1], features[0]),
        )
        searched += [_searched(context, k, tested, rng) for k in tested]
        absent += _absent(context, rng)
    offsets = {USED: [s.offset for s in searched if s.direction == 1]}
    for also in ALSO_USED:
        offsets[also] = _band_offsets(pair, (taps1, taps2), friend2, order, also)
    return SceneRun(
        index,
        stream,
        count,
        True,
        result.method,
        searched,
        absent,
        offsets,
        render_seconds,
        sift_seconds,
    )


def answer(
    pair: RenderedPair, points1: Array, points2: Array, friend2: Array, sigma: float = SIGMA
) -> SolveResult | None:
    """``solve``'s answer with phone cameras from these taps (noise ``sigma`` px), or None
    when it has no uncertainty of F (no band to search)."""
    scene = pair.scene
    try:
        result = solve(
            points1,
            points2,
            epipole1=friend2,
            tap_sigma=sigma,
            image_size1=scene.image_size1,
            image_size2=scene.image_size2,
            camera1="phone",
            camera2="phone",
            fundamental_covariance=True,
        )
    except SolverError:
        return None
    return result if result.fundamental_covariance is not None else None


def _by_kind(pair: RenderedPair, candidates: Indices) -> list[int]:
    """Up to PER_KIND landmarks of each kind, in the (random) order given."""
    taken: dict[str, int] = {}
    chosen = []
    for k in candidates:
        kind = pair.kinds[k]
        if taken.get(kind, 0) < PER_KIND:
            taken[kind] = taken.get(kind, 0) + 1
            chosen.append(int(k))
    return chosen


def _searched(context: _Direction, k: int, tested: list[int], rng: np.random.Generator) -> Searched:
    truth = context.truths_b[k]
    point = context.taps_a[k]
    diagonal = math.hypot(*context.size_b)
    kind = context.pair.kinds[k]
    others = [j for j in tested if j != k]
    swap = context.truths_b[int(rng.choice(others))] if others else truth
    angle = rng.uniform(0.0, 2 * math.pi)
    distance = rng.uniform(*WRONG_OFFSET) * diagonal
    moved = truth + distance * np.array([math.cos(angle), math.sin(angle)])
    right_tap = truth + rng.normal(0.0, SIGMA, 2)
    band = epipolar_band(context.epipolar, point, image_size=context.size_b, point_covariance=TAP)
    if band is None:
        nan = math.nan
        return Searched(
            context.index, context.direction, kind, nan, nan, 0.0, None, None, truth,
            diagonal, None, nan, nan, nan,
        )  # fmt: skip
    offset = abs(band.line[:2] @ truth + band.line[2]) / float(band.sd(truth[None])[0])
    colour = timed_search(context.photo_a, context.photo_b, point, context.epipolar, band)
    grey = sift = None
    if context.grey is not None and context.features is not None:
        grey = timed_search(*context.grey, point, context.epipolar, band)
        sift = sift_match(*context.features, point, context.epipolar, band)
    return Searched(
        context.index,
        context.direction,
        kind,
        float(offset),
        float(band.half_width(truth[None])[0]),
        band.length,
        colour,
        grey,
        truth,
        diagonal,
        sift,
        band.check(right_tap, TAP).sigmas,
        band.check(swap, TAP).sigmas,
        band.check(moved, TAP).sigmas,
    )


def timed_search(
    photo_a: Image,
    photo_b: Image,
    point: Array,
    epipolar: Epipolar,
    band: Band,
    *,
    covariance: Array = TAP,
    always_back: bool = True,
    rules: Rules = RULES,
) -> Timed:
    """The evidence, and the wall and CPU time ``suggest`` spends on it: the search along
    the band, and the search back only when the match may be offered (as ``suggest`` does).
    The search back is made for every match that leads or stands out in its context,
    offered or not (to count the rule without ``max_across`` too), and with
    ``always_back`` for every match (to weigh other rules), but timed only as ``suggest``
    would make it."""
    search = LandmarkSearch(photo_a, photo_b, point, epipolar, band, point_covariance=covariance)
    wall, cpu = time.perf_counter(), time.process_time()
    evidence = gather(search, rules=rules)
    forward = (time.perf_counter() - wall, time.process_time() - cpu)
    if evidence is None:
        return Timed(None, *forward)
    counted = offerable(evidence.match, rules)
    if not (leads(evidence.match, rules) or stands_out(evidence.match, rules) or always_back):
        return Timed(evidence, *forward)
    wall, cpu = time.perf_counter(), time.process_time()
    checked = check_back(evidence, search, rules=rules)
    back = (time.perf_counter() - wall, time.process_time() - cpu)
    share = 1.0 if counted else 0.0
    return Timed(checked, forward[0] + share * back[0], forward[1] + share * back[1])


def _absent(context: _Direction, rng: np.random.Generator) -> list[Absent]:
    pair = context.pair
    only = pair.only1 if context.direction == 1 else pair.only2
    camera_a = pair.scene.camera1 if context.direction == 1 else pair.scene.camera2
    spots = []
    for k in rng.permutation(len(only))[:ABSENT]:
        point = camera_a.project(only[k][None])[0] + rng.normal(0.0, SIGMA, 2)
        band = epipolar_band(
            context.epipolar, point, image_size=context.size_b, point_covariance=TAP
        )
        colour = (
            None
            if band is None
            else timed_search(context.photo_a, context.photo_b, point, context.epipolar, band)
        )
        spots.append(Absent(context.index, context.direction, band is not None, colour))
    return spots


def _band_offsets(
    pair: RenderedPair, taps: tuple[Array, Array], friend2: Array, order: Indices, used: int
) -> list[float]:
    """Offsets (sd) of the true landmarks from their bands when the answer used the first
    ``used`` landmarks of ``order`` (the rest are checked)."""
    scene = pair.scene
    if len(order) < used + 1:
        return []
    chosen, rest = order[:used], order[used:]
    result = answer(pair, taps[0][chosen], taps[1][chosen], friend2)
    if result is None:
        return []
    epipolar = Epipolar.from_result(
        result, tapped_in=1, landmarks1=taps[0][chosen], landmarks2=taps[1][chosen]
    )
    assert epipolar is not None
    offsets = []
    for k in rest:
        band = epipolar_band(
            epipolar, taps[0][k], image_size=scene.image_size2, point_covariance=TAP
        )
        if band is None:
            continue
        truth = scene.landmarks2[k]
        offsets.append(abs(band.line[:2] @ truth + band.line[2]) / float(band.sd(truth[None])[0]))
    return offsets


def _grey(photo: Image) -> Image:
    """The photo in grey, kept 3-channel-free: what the search sees without colour."""
    return np.asarray(cv2.cvtColor(photo, cv2.COLOR_BGR2GRAY), dtype=np.uint8)
