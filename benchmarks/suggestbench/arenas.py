"""One rendered arena, searched as a person would use the suggestions.

An arena (``testbed.venue.rendered_arena``: a hall with banners seen from both sides, mats,
signs and posters alike, pillars alike, a video board, moving spotlights) is photographed
from both ends. A person picks 10 landmarks both photos show, as different as they can:
one of each kind of thing in turn, at least 3 % of the diagonal apart in both photos.
Friend 1 marks friend 2; both tap the first 3 (or 5) landmarks; ``solve`` answers with
phone cameras; each of the other landmarks, tapped in one photo, is looked for in the other
(both ways). Every tap has Gaussian noise of 1, 3 or 8 px per axis (one draw each, the
answer's ``tap_sigma`` the same). Every random draw comes from the arena's own seed.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from shared_solver import SolveResult
from shared_solver.matching import Epipolar, epipolar_band
from shared_solver.matching.suggestion import RULES
from shared_solver.projective import Array
from testbed.venue import RenderedPair, rendered_arena

from .trials import BEFORE, SEED, Timed, answer, miss, timed_search

# Held out: stream 9. Looked at for choices: streams 4 (held out until its wrong spots, all
# in bands far wider than the rows searched, led to the rule's max_across), 5, 6 (held out
# until its wrong spots were looked at, before the context), 7 (the context's thresholds
# chosen) and 8 (they checked).
ARENA_STREAMS = {"calibration": 3, "evaluation": 9}
PICKED = 10  # landmarks a person picks in each arena
APART = 0.03  # least distance between two of them, fraction of each photo's diagonal
FOUND = (3, 5)  # landmarks tapped in both photos before the others are looked for
SIGMAS = (1.0, 3.0, 8.0)  # px per axis: a careful tap, the server's default, a quick one


@dataclass(frozen=True)
class Asked:
    """One landmark tapped in photo A and looked for in photo B.

    Attributes:
        scene: the arena's index; sigma: the taps' noise, px; found: landmarks tapped in
            both photos; direction: 1 if tapped in photo 1 (looked for in photo 2).
        kind: what it lies on; diagonal: photo B's diagonal, px; truth: (2,) where it is
            in photo B.
        half_width: the band's half-width at the truth, px (NaN when it misses photo B).
        timed: the search (None when the band misses photo B).
        before: the search as it was before it had two views, with ``compare`` (as read
            alone, the search back made when the match leads under the rule before).
    """

    scene: int
    sigma: float
    found: int
    direction: int
    kind: str
    diagonal: float
    truth: Array
    half_width: float
    timed: Timed | None
    before: Timed | None = None

    def error(self, timed: Timed | None) -> float:
        """The match's distance from the truth, fraction of the diagonal (NaN: none)."""
        return miss(timed, self.truth, self.diagonal)


@dataclass(frozen=True)
class ArenaRun:
    """Everything measured on one arena (``picked`` below :data:`PICKED`: not used)."""

    index: int
    stream: str
    landmarks: int
    picked: int
    distance: float
    kinds: tuple[str, ...]
    asked: list[Asked]
    render_seconds: float


def arena_seed(stream: str, index: int) -> tuple[int, int, int]:
    return (SEED, ARENA_STREAMS[stream], index)


def run_arena(stream: str, index: int, *, always_back: bool, compare: bool = False) -> ArenaRun:
    """Render arena ``index`` of ``stream`` and ask for its landmarks (module docstring);
    ``always_back``: make the search back for every match, to weigh other rules;
    ``compare``: search as before too."""
    started = time.perf_counter()
    pair = rendered_arena(arena_seed(stream, index))
    render_seconds = time.perf_counter() - started
    scene = pair.scene
    rng = np.random.default_rng((*arena_seed(stream, index), 1))
    chosen = pick(pair, rng)
    distance = float(np.linalg.norm(scene.camera2.centre - scene.camera1.centre))
    kinds = tuple(pair.kinds[k] for k in chosen)
    run = ArenaRun(index, stream, len(scene.points), len(chosen), distance, kinds, [], 0.0)
    if len(chosen) < PICKED:
        return run
    asked: list[Asked] = []
    for sigma in SIGMAS:
        taps1 = scene.landmarks1 + rng.normal(0.0, sigma, scene.landmarks1.shape)
        taps2 = scene.landmarks2 + rng.normal(0.0, sigma, scene.landmarks2.shape)
        friend2 = scene.epipole1 + rng.normal(0.0, sigma, 2)
        for found in FOUND:
            used, rest = chosen[:found], chosen[found:]
            result = answer(pair, taps1[used], taps2[used], friend2, sigma)
            if result is None:
                continue
            for direction in (1, 2):
                asked += _ask(
                    pair,
                    _Setting(index, sigma, found, direction, always_back, compare),
                    result,
                    taps=(taps1, taps2),
                    used=used,
                    rest=rest,
                )
    return ArenaRun(
        index, stream, len(scene.points), len(chosen), distance, kinds, asked, render_seconds
    )


def pick(pair: RenderedPair, rng: np.random.Generator) -> list[int]:
    """Up to :data:`PICKED` landmarks as a person picks them: a kind of thing at a time (in
    a random order, round and round), at random within it, never near one already picked."""
    scene = pair.scene
    diagonals = (math.hypot(*scene.image_size1), math.hypot(*scene.image_size2))
    kinds = sorted(set(pair.kinds))
    rng.shuffle(kinds)
    left = {
        kind: [int(k) for k in rng.permutation(np.flatnonzero(np.array(pair.kinds) == kind))]
        for kind in kinds
    }
    chosen: list[int] = []

    def apart(k: int) -> bool:
        return all(
            np.hypot(*(points[k] - points[j])) > APART * diagonal
            for j in chosen
            for points, diagonal in zip(
                (scene.landmarks1, scene.landmarks2), diagonals, strict=True
            )
        )

    while len(chosen) < PICKED and any(left.values()):
        for kind in kinds:
            while left[kind]:
                k = left[kind].pop()
                if apart(k):
                    chosen.append(k)
                    break
            if len(chosen) == PICKED:
                break
    return chosen


@dataclass(frozen=True)
class _Setting:
    """What one round of asking shares."""

    scene: int
    sigma: float
    found: int
    direction: int
    always_back: bool
    compare: bool


def _ask(
    pair: RenderedPair,
    setting: _Setting,
    result: SolveResult,
    *,
    taps: tuple[Array, Array],
    used: list[int],
    rest: list[int],
) -> list[Asked]:
    """Each landmark of ``rest``, tapped in photo ``setting.direction``, looked for in the
    other under the answer from ``used``."""
    scene = pair.scene
    first = setting.direction == 1
    epipolar = Epipolar.from_result(
        result, tapped_in=1 if first else 2, landmarks1=taps[0][used], landmarks2=taps[1][used]
    )
    assert epipolar is not None
    photo_a, photo_b = (pair.photo1, pair.photo2) if first else (pair.photo2, pair.photo1)
    taps_a = taps[0] if first else taps[1]
    truths = scene.landmarks2 if first else scene.landmarks1
    size_b = scene.image_size2 if first else scene.image_size1
    covariance = setting.sigma**2 * np.eye(2)
    asked = []
    for k in rest:
        band = epipolar_band(epipolar, taps_a[k], image_size=size_b, point_covariance=covariance)
        timed = before = None
        if band is not None:
            # The search now, and (with compare) as before, on the same tap and band.
            ways = [(RULES, setting.always_back), (BEFORE, False)][: 2 if setting.compare else 1]
            found = [
                timed_search(
                    photo_a,
                    photo_b,
                    taps_a[k],
                    epipolar,
                    band,
                    covariance=covariance,
                    always_back=always_back,
                    rules=rules,
                )
                for rules, always_back in ways
            ]
            timed, before = found[0], found[1] if setting.compare else None
        asked.append(
            Asked(
                setting.scene,
                setting.sigma,
                setting.found,
                setting.direction,
                pair.kinds[k],
                math.hypot(*size_b),
                truths[k],
                math.nan if band is None else float(band.half_width(truths[k][None])[0]),
                timed,
                before,
            )
        )
    return asked
