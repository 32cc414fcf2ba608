"""The best place along a band for a landmark's patch: template matching in epipolar
coordinates (:mod:`.polar`), coarse to fine.

In those coordinates the two views of a patch differ by a stretch along the lines and a
shear, both unknown (they depend on the surface's depth and slant in each view). The
search tries a grid of both with OpenCV's normalised cross-correlation
(``cv2.matchTemplate``, ``TM_CCOEFF_NORMED``: insensitive to each phone's exposure and
white balance), in colour:

1. at half resolution, every stretch and shear of a coarse grid, over the whole band;
2. at full resolution, a finer grid around the few best places found (each more than
   ``exclusion`` px from the others of its view), and the best of each view.

The patch is matched in two **views** (:data:`VIEWS`). A surface both phones see from its
front (the floor, a wall, a board) shows it *as read*. *Reversed along* the lines is how a
surface seen from its two sides shows it (a banner hung between the phones, its print
showing through), and how many look-alikes show it: a print that reads the same from both
sides, the other corner of a mat whose print is the same turned 180 degrees, the other
edge of a pillar alike. The best place of either view is the match; the best place of
either view further than ``exclusion`` along the band is its runner-up (a repeated
pattern, a row of seats, a look-alike make the two close); where both views find one spot,
the place as read is the match. A match read reversed also carries the best score of the
patch as read: the rule (:mod:`.suggestion`) can ask it to lead that, but by default does
not offer it, since on the rendered halls and arenas that view found look-alikes (a box's
corner, a floor marking, a pillar's edge read the other way) too often beside the banners
seen from behind it finds (docs/geometry.md, "Finding a landmark in the other photo").

Each place found is also scored in its **context**: a patch twice the size around the tap,
read the same way, stretched and sheared as the place found it, and matched at it (within
2 px along the lines and a row across). Look-alikes (a mat or a sign alike, another banner
of one design) are alike in the small patch, seldom in what surrounds them; the rule can
then tell apart two places the small patch cannot.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from ..projective import Array
from .polar import Image, PolarFrame

# Stretches along the lines (B's length over A's) and shears (px of B per row) tried at
# half resolution; then each best one and its neighbours at full resolution. The range
# covers most landmarks of the rendered halls (docs/suggestions.md): beyond a stretch of
# 3 one view holds too few pixels of the patch to match.
COARSE_STRETCHES = (0.35, 0.5, 0.7, 1.0, 1.4, 2.0, 2.8)
COARSE_SHEARS = (-3.0, 0.0, 3.0)
_FINE_STRETCH_STEP = 1.19
_FINE_SHEAR_STEP = 1.0
_CANDIDATES = 4  # places refined at full resolution
_REFINE_REACH = 12  # px: how far a refined place may move from its coarse one


# How the patch is read against photo B: the step along its columns (its rows are the
# epipolar lines, which correspond one to one whatever the surface).
VIEWS: dict[str, int] = {"as read": 1, "reversed along": -1}


@dataclass(frozen=True)
class Match:
    """The best place for the patch along the band.

    Attributes:
        point: (2,) in photo B, px.
        score: its normalised cross-correlation (-1 to 1).
        runner_up: the best score of any view further than ``exclusion`` along the band
            (-1 if none).
        stretch, shear: the local change of shape that matched best.
        view: the view of the patch that matched (:data:`VIEWS`).
        as_read: with a match of another view, the best score of the patch as read
            anywhere along the band, near the match included (its own score otherwise).
        as_read_apart: how far along the band that place is from the match, px (a
            fraction of photo B's diagonal once :func:`.suggestion.search_band` has it).
        across: the band's half-width at the match, in strip rows
            (:meth:`.polar.PolarFrame.across`), however many the strip has: beyond its
            margin, places of the band beside the strip were not searched.
        context: the match's score in its context (module docstring; -1 when not scored).
        context_runner_up: the best context score of any other place found further than
            ``exclusion`` along the band (-1 if none).
    """

    point: Array
    score: float
    runner_up: float
    stretch: float
    shear: float
    view: str = "as read"
    as_read: float = -1.0
    as_read_apart: float = 0.0
    across: float = 0.0
    context: float = -1.0
    context_runner_up: float = -1.0


@dataclass
class _Best:
    """Per strip column, the best score found so far and what gave it."""

    score: Array
    row: Array
    stretch: Array
    shear: Array

    @classmethod
    def empty(cls, columns: int) -> _Best:
        return cls(np.full(columns, -2.0), np.zeros(columns), np.ones(columns), np.zeros(columns))

    def add(
        self,
        strip: Image,
        patch: Image,
        stretches: tuple[float, ...],
        shear: float,
        reach: Array,
    ) -> None:
        """Match ``patch`` stretched by each factor along ``strip``; keep per column (the
        template's centre) the best over factors and over the rows within ``reach`` (per
        column) of the middle one."""
        height = patch.shape[0]
        for stretch in stretches:
            width = max(3, round(patch.shape[1] * stretch))
            if width >= strip.shape[1] or height > strip.shape[0]:
                continue
            template = cv2.resize(
                patch,
                (width, height),
                interpolation=cv2.INTER_AREA if stretch < 1 else cv2.INTER_LINEAR,
            )
            scores = cv2.matchTemplate(strip, template, cv2.TM_CCOEFF_NORMED)
            columns = np.arange(scores.shape[1]) + (width - 1) // 2
            offsets = np.abs(np.arange(scores.shape[0]) - (scores.shape[0] - 1) / 2)
            scores[offsets[:, None] > reach[columns][None, :]] = -2.0
            best_rows = scores.argmax(axis=0)
            best = scores[best_rows, np.arange(scores.shape[1])]
            better = best > self.score[columns]
            chosen = columns[better]
            self.score[chosen] = best[better]
            self.row[chosen] = best_rows[better]
            self.stretch[chosen] = stretch
            self.shear[chosen] = shear


@dataclass(frozen=True)
class Place:
    """A refined place along the band, in one view (``column``: index into the band's
    distances ``t``; ``row``: the template's top row in the strip)."""

    score: float
    column: int
    row: int
    stretch: float
    shear: float
    view: str


def best_match(
    frame: PolarFrame,
    t: Array,
    *,
    exclusion: float,
    views: tuple[str, ...] = tuple(VIEWS),
    context: PolarFrame | None = None,
) -> Match | None:
    """The best place for ``frame.patch`` at distances ``t`` (1 px apart) from ``e_B``.

    Args:
        frame: the landmark's patch and photo B in epipolar coordinates.
        t: (N,) distances along the band, px, increasing by 1.
        exclusion: px along the band within which two places are the same one.
        views: the views searched, "as read" among them (:data:`VIEWS`; before there were
            views, the patch was searched as read alone).
        context: the same frame with a larger patch (the same margin, so the same rows),
            to score every place found in its context; None: not scored.
    """
    found = places(frame, t, exclusion=exclusion, views=views)
    if not found:
        return None
    best = max(found, key=lambda place: place.score)
    read = max(
        (place for place in found if place.view == "as read"),
        key=lambda place: place.score,
        default=best,
    )
    if abs(read.column - best.column) <= exclusion:
        best = read  # both views find one spot: the patch as read places it
    others = [place for place in found if abs(place.column - best.column) > exclusion]
    runner_up = max((place.score for place in others), default=-1.0)
    own = rivals = -1.0
    if context is not None:
        own = in_context(context, t, best)
        rivals = max((in_context(context, t, place) for place in others), default=-1.0)
    return Match(
        point_of(frame, t, best),
        best.score,
        runner_up,
        best.stretch,
        best.shear,
        best.view,
        read.score if read.view == "as read" else -1.0,
        float(abs(read.column - best.column)),
        float(frame.across(t[best.column : best.column + 1])[0]),
        own,
        rivals,
    )


_CONTEXT_ALONG = 2  # columns either side of a place where its context may match best


def in_context(frame: PolarFrame, t: Array, place: Place) -> float:
    """The score of ``frame.patch`` (the larger one) at ``place``: read in the place's
    view, stretched and sheared as it found, its top row within one of the place's (the
    frames share their margin, so their templates' top rows count alike) and its centre
    within ``_CONTEXT_ALONG`` columns."""
    patch = np.ascontiguousarray(frame.patch[:, :: VIEWS[place.view]])
    height = patch.shape[0]
    width = max(3, round(patch.shape[1] * place.stretch))
    template = cv2.resize(
        patch,
        (width, height),
        interpolation=cv2.INTER_AREA if place.stretch < 1 else cv2.INTER_LINEAR,
    )
    reach = width // 2 + _CONTEXT_ALONG + 1
    along = float(t[place.column]) + np.arange(-reach, reach + 1, dtype=float)
    scores = cv2.matchTemplate(frame.strip(along, place.shear), template, cv2.TM_CCOEFF_NORMED)
    centres = np.arange(scores.shape[1]) + (width - 1) // 2
    near = np.abs(centres - reach) <= _CONTEXT_ALONG
    rows = scores[max(0, place.row - 1) : place.row + 2][:, near]
    return float(rows.max()) if rows.size else -1.0


def point_of(frame: PolarFrame, t: Array, place: Place) -> Array:
    """(2,) the photo-B pixel of a place: the template's centre row is ``radius`` below its
    top row."""
    return frame.point(place.row + frame.radius, float(t[place.column]))


def places(
    frame: PolarFrame, t: Array, *, exclusion: float, views: tuple[str, ...] = tuple(VIEWS)
) -> list[Place]:
    """The best places along the band, refined (see :func:`best_match`): the
    ``_CANDIDATES`` best coarse places over both views, and the best of each view."""
    if len(t) < 2 * frame.radius + 2:
        return []
    reach = frame.reach(t)
    coarse_reach = (reach[::2] + 1) // 2  # rows at half resolution
    strips = {shear: half(frame.strip(t, shear)) for shear in COARSE_SHEARS}
    patches = {view: np.ascontiguousarray(frame.patch[:, :: VIEWS[view]]) for view in views}
    coarse = {view: _Best.empty((len(t) + 1) // 2) for view in views}
    peaks: list[tuple[float, str, int]] = []
    for view, patch in patches.items():
        small = half(patch)
        for shear, strip in strips.items():
            coarse[view].add(strip, small, COARSE_STRETCHES, shear, coarse_reach)
        scores = coarse[view].score
        peaks += [(float(scores[c]), view, c) for c in _distinct_peaks(scores, exclusion / 2)]
    peaks.sort(reverse=True)
    chosen = peaks[:_CANDIDATES]
    for view in views:
        best = next((peak for peak in peaks if peak[1] == view), None)
        if best is not None and best not in chosen:
            chosen.append(best)
    found: list[Place] = []
    for _, view, column in chosen:
        place = _refine(
            frame, patches[view], t, reach, coarse=coarse[view], coarse_column=column, view=view
        )
        if place is not None:
            found.append(place)
    return found


def half(image: Image) -> Image:
    """The image at half resolution (``cv2.pyrDown``: blurred, then every other pixel)."""
    return np.asarray(cv2.pyrDown(image), dtype=np.uint8)


def _distinct_peaks(scores: Array, exclusion: float) -> list[int]:
    """Up to ``_CANDIDATES`` columns of the highest scores, each more than ``exclusion``
    columns from the ones before."""
    peaks: list[int] = []
    for column in np.argsort(-scores):
        if scores[column] <= -1.0:
            break
        if all(abs(int(column) - other) > exclusion for other in peaks):
            peaks.append(int(column))
            if len(peaks) == _CANDIDATES:
                break
    return peaks


def _refine(
    frame: PolarFrame,
    patch: Image,
    t: Array,
    reach: Array,
    *,
    coarse: _Best,
    coarse_column: int,
    view: str,
) -> Place | None:
    """The best place for ``patch`` (``frame.patch`` in ``view``) within ``_REFINE_REACH``
    of a coarse one, over a finer grid around its stretch and shear, at full
    resolution."""
    column = 2 * coarse_column
    stretch, shear = float(coarse.stretch[coarse_column]), float(coarse.shear[coarse_column])
    half = int(frame.radius * max(stretch * _FINE_STRETCH_STEP, 1.0)) + 1
    low = max(0, column - _REFINE_REACH - half)
    high = min(len(t), column + _REFINE_REACH + half + 1)
    stretches = (stretch / _FINE_STRETCH_STEP, stretch, stretch * _FINE_STRETCH_STEP)
    best: Place | None = None
    for sheared in (shear - _FINE_SHEAR_STEP, shear, shear + _FINE_SHEAR_STEP):
        window = _Best.empty(high - low)
        window.add(frame.strip(t[low:high], sheared), patch, stretches, sheared, reach[low:high])
        near = np.arange(high - low) + low
        reachable = np.abs(near - column) <= _REFINE_REACH
        if not reachable.any():
            continue
        index = int(np.flatnonzero(reachable)[np.argmax(window.score[reachable])])
        score = float(window.score[index])
        if score > -1.0 and (best is None or score > best.score):
            best = Place(
                score,
                low + index,
                int(window.row[index]),
                float(window.stretch[index]),
                float(window.shear[index]),
                view,
            )
    return best
