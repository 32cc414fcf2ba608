"""The best place along a band for a landmark's patch: template matching in epipolar
coordinates (:mod:`.polar`), coarse to fine.

In those coordinates the two views of a patch differ by a stretch along the lines and a
shear, both unknown (they depend on the surface's depth and slant in each view). The
search tries a grid of both with OpenCV's normalised cross-correlation
(``cv2.matchTemplate``, ``TM_CCOEFF_NORMED``: insensitive to each phone's exposure and
white balance), in colour:

1. at half resolution, every stretch and shear of a coarse grid, over the whole band;
2. at full resolution, a finer grid around each of the few best places found that are
   more than ``exclusion`` px apart.

The best refined place is the match; the best other one, further than ``exclusion`` along
the band, is its runner-up (a repeated pattern, a row of seats, makes the two close).
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


@dataclass(frozen=True)
class Match:
    """The best place for the patch along the band.

    Attributes:
        point: (2,) in photo B, px.
        score: its normalised cross-correlation (-1 to 1).
        runner_up: the best score further than ``exclusion`` along the band (-1 if none).
        stretch, shear: the local change of shape that matched best.
    """

    point: Array
    score: float
    runner_up: float
    stretch: float
    shear: float


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


def best_match(frame: PolarFrame, t: Array, *, exclusion: float) -> Match | None:
    """The best place for ``frame.patch`` at distances ``t`` (1 px apart) from ``e_B``.

    Args:
        frame: the landmark's patch and photo B in epipolar coordinates.
        t: (N,) distances along the band, px, increasing by 1.
        exclusion: px along the band within which two places are the same one.
    """
    if len(t) < 2 * frame.radius + 2:
        return None
    coarse = _Best.empty((len(t) + 1) // 2)
    small_patch = coarse_view(frame.patch)
    reach = frame.reach(t)
    coarse_reach = (reach[::2] + 1) // 2  # rows at half resolution
    for shear in COARSE_SHEARS:
        coarse.add(
            coarse_view(frame.strip(t, shear)), small_patch, COARSE_STRETCHES, shear, coarse_reach
        )
    refined = [
        found
        for column in _distinct_peaks(coarse.score, exclusion / 2)
        if (found := _refine(frame, t, reach, coarse=coarse, coarse_column=column)) is not None
    ]
    if not refined:
        return None
    refined.sort(key=lambda found: -found[0])
    score, column, row, stretch, shear = refined[0]
    runner_up = max(
        (other[0] for other in refined[1:] if abs(other[1] - column) > exclusion), default=-1.0
    )
    # The template's centre row is ``radius`` below its top row.
    point = frame.point(row + frame.radius, float(t[column]))
    return Match(point, score, runner_up, stretch, shear)


COARSE_GREY = False


def coarse_view(image: Image) -> Image:
    if COARSE_GREY and image.ndim == 3:
        image = np.asarray(cv2.cvtColor(image, cv2.COLOR_BGR2GRAY), dtype=np.uint8)
    return half(image)


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
    frame: PolarFrame, t: Array, reach: Array, *, coarse: _Best, coarse_column: int
) -> tuple[float, int, int, float, float] | None:
    """(score, column, row, stretch, shear) of the best place within ``_REFINE_REACH`` of a
    coarse one, over a finer grid around its stretch and shear, at full resolution."""
    column = 2 * coarse_column
    stretch, shear = float(coarse.stretch[coarse_column]), float(coarse.shear[coarse_column])
    half = int(frame.radius * max(stretch * _FINE_STRETCH_STEP, 1.0)) + 1
    low = max(0, column - _REFINE_REACH - half)
    high = min(len(t), column + _REFINE_REACH + half + 1)
    stretches = (stretch / _FINE_STRETCH_STEP, stretch, stretch * _FINE_STRETCH_STEP)
    best: tuple[float, int, int, float, float] | None = None
    for sheared in (shear - _FINE_SHEAR_STEP, shear, shear + _FINE_SHEAR_STEP):
        window = _Best.empty(high - low)
        window.add(
            frame.strip(t[low:high], sheared), frame.patch, stretches, sheared, reach[low:high]
        )
        near = np.arange(high - low) + low
        reachable = np.abs(near - column) <= _REFINE_REACH
        if not reachable.any():
            continue
        index = int(np.flatnonzero(reachable)[np.argmax(window.score[reachable])])
        score = float(window.score[index])
        if score > -1.0 and (best is None or score > best[0]):
            best = (
                score,
                low + index,
                int(window.row[index]),
                float(window.stretch[index]),
                float(window.shear[index]),
            )
    return best
