"""Several exact geometries fit: which is the likeliest? Ranking the roots of minimal solvers.

The six-landmark line solver and the 7-point method return up to three geometries that fit
their landmarks exactly. They are ranked by physical plausibility
(:mod:`.plausibility`): the oriented epipolar constraint first, then real focal lengths,
then camera-like ones, then how close they are to a phone's.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from numpy.typing import ArrayLike

from .. import validation
from ..errors import Reason
from ..minimal.six_point_line import six_point_line_roots
from ..projective import Array
from ..refusal import SolverError
from .plausibility import Plausibility, assess


@dataclass(frozen=True)
class EpipoleCandidate:
    """One real solution: homogeneous epipoles, its F, and its rank (1 = most plausible).

    Fields are readable as attributes or by name (``candidate["epipole2"]``), like the JSON.
    """

    epipole1: Array
    epipole2: Array
    fundamental: Array
    rank: int
    plausibility: Plausibility

    def __getitem__(self, name: str) -> Any:
        return getattr(self, name)


def epipoles_from_six(
    line1: ArrayLike,
    pts1: ArrayLike,
    pts2: ArrayLike,
    *,
    image_size1: tuple[float, float] | None = None,
    image_size2: tuple[float, float] | None = None,
) -> list[EpipoleCandidate]:
    """Every geometry with friend 2 on ``line1`` that fits 6 landmarks (paper 3.3), ranked.

    Args:
        line1: (3,) line ``(a, b, c)``, ``a x + b y + c = 0`` in photo-1 pixels, through
            friend 2 (epipole 1).
        pts1: (6, 2) landmarks in photo 1, pixels.
        pts2: (6, 2) the same landmarks in photo 2, pixels.
        image_size1, image_size2: (width, height) of the photos, for the plausibility of the
            implied focal lengths and whether epipoles fall inside; optional.

    Returns:
        Candidates ordered by ``rank`` (1 first): the oriented epipolar constraint, then
        real, camera-like, phone-like implied focal lengths. Each has
        ``epipole1``, ``epipole2`` (3,) homogeneous unit vectors, ``fundamental`` (3, 3).

    Raises:
        SolverError: invalid or degenerate input, or no real solution.
    """
    line = validation.line(line1, "line1")
    p, q = validation.landmark_pairs(pts1, pts2, minimum=6, maximum=6)
    roots = six_point_line_roots(line, p, q)
    if not roots:
        raise SolverError(Reason.LINE_FITS_NOTHING)
    cues = [
        assess(f, e1, e2, p, q, image_size1=image_size1, image_size2=image_size2)
        for e1, e2, f in roots
    ]
    order = sorted(range(len(roots)), key=lambda i: cues[i].sort_key())
    return [
        EpipoleCandidate(*roots[i], rank=rank, plausibility=cues[i])
        for rank, i in enumerate(order, 1)
    ]
