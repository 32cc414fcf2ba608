"""Is a candidate geometry physically possible for two phone cameras?

Used to rank the several real solutions of the 6-landmark cubic and of the 7-point method:

* the oriented epipolar constraint (Chum, Werner & Pajdla 2004): every landmark lies in front
  of both cameras only if ``(e2 x q_i) . (F p_i)`` has the same sign for all ``i``;
* the focal lengths a candidate ``F`` implies when each principal point is the image centre
  (Bougnoux, ICCV 1998; docs/geometry.md): they
  must be real and phone-like;
* whether the epipoles fall inside the photos is reported, but it does not rank: two
  phones facing each other see each other, but a room's cameras, a turntable or two people
  walking one behind the other do not, and ranking by it chose the wrong root more often
  than leaving it out (measured on those scenes, exact taps; docs/geometry.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import linalg
from ..projective import Array, homogeneous, skew

# A phone's focal length in pixels relative to the long side of the photo: ultra-wide
# (13 mm equivalent, about 0.36) to 3x tele (77 mm, about 2.1), with margin.
PHONE_FOCAL_RANGE = (0.25, 3.5)
# The main camera of a phone (about 26 mm equivalent): the tie-breaker between candidates
# that pass every hard cue.
TYPICAL_PHONE_FOCAL = 0.75


@dataclass(frozen=True)
class Plausibility:
    """How physically possible a candidate geometry is (fewer violations rank first)."""

    oriented_violations: int
    focal_lengths: tuple[float | None, float | None]
    phone_like: bool
    epipoles_inside: int
    focal_deviation: float  # sum of |log(f / typical phone f)|, inf if imaginary

    def hard_cues(self) -> tuple[int, int, int]:
        """What a real scene must satisfy (every landmark in front of both cameras, real
        focal lengths, and camera-like ones); candidates equal here are genuinely ambiguous."""
        imaginary = sum(focal is None for focal in self.focal_lengths)
        return (self.oriented_violations, imaginary, 0 if self.phone_like else 1)

    def sort_key(self) -> tuple[int, int, int, float]:
        return (*self.hard_cues(), self.focal_deviation)


def oriented_violations(fundamental: Array, e2: Array, p: Array, q: Array) -> int:
    """How many landmarks break the oriented epipolar constraint (minority sign count).

    Args:
        fundamental: (3, 3) F with ``q^T F p = 0``.
        e2: (3,) epipole in photo 2 (``F^T e2 = 0``).
        p, q: (N, 2) landmarks in photo 1 and photo 2, pixels.
    """
    # (e2 x q_i) . (F p_i), with e2 x q_i = [e2]x q_i
    lines = homogeneous(q) @ skew(e2).T
    signs = np.einsum("ij,ij->i", lines, homogeneous(p) @ fundamental.T)
    positive = int((signs > 0).sum())
    return min(positive, len(signs) - positive)


def orient_epipole2(
    fundamental: Array, e1: Array, e2: Array, p: Array, q: Array
) -> tuple[Array, bool]:
    """``e2`` with the sign of the true ``P2 C1``, given ``e1`` with the sign of ``P1 C2``.

    For oriented epipoles the two oriented constraints, ``(e2 x q).(F p)`` and
    ``(e1 x p).(F^T q)``, have the same sign for every landmark in front of both cameras,
    whatever the sign of F (checked on facing and turned-away scenes). With ``e1`` oriented
    (friend 2 is in front of friend 1's camera: ``w > 0``) this fixes ``e2``: ``w > 0``
    means friend 1 is in front of friend 2's camera, ``w < 0`` behind it, and at ``w = 0``
    the direction ``(x, y)`` is the true one. The landmarks vote.

    Args:
        fundamental: (3, 3) F, any sign; e1: (3,) oriented; e2: (3,) any sign.
        p, q: (N, 2) landmarks, pixels.

    Returns:
        (oriented e2, whether F is orientable: every landmark on the same side in both
        photos). A noisy fit can break the constraint for some landmarks (it is then not a
        physical geometry) and its orientation must not be trusted.
    """
    ph, qh = homogeneous(p), homogeneous(q)
    # e x r = [e]x r for every row r at once
    signs2 = np.sign(np.einsum("ij,ij->i", qh @ skew(e2).T, ph @ fundamental.T))
    signs1 = np.sign(np.einsum("ij,ij->i", ph @ skew(e1).T, qh @ fundamental))
    orientable = bool(abs(signs2.sum()) == len(signs2) and abs(signs1.sum()) == len(signs1))
    return (e2 if float(signs2 @ signs1) >= 0 else -e2), orientable


def implied_focal_lengths(
    fundamental: Array, e1: Array, e2: Array, centre1: Array, centre2: Array
) -> tuple[float | None, float | None]:
    """Focal lengths (px) of both cameras implied by F, square pixels and known principal points.

    Bougnoux's formula; None where the implied squared focal length is not positive.

    Args:
        fundamental: (3, 3) F; e1, e2: (3,) its epipoles in photo 1 and 2.
        centre1, centre2: (2,) principal points (image centres), pixels.
    """
    c1 = np.array([float(centre1[0]), float(centre1[1]), 1.0])
    c2 = np.array([float(centre2[0]), float(centre2[1]), 1.0])
    f = fundamental

    def squared(f_: Array, e_other: Array, c: Array, c_other: Array) -> float:
        # c'^T [e']x diag(1, 1, 0) F, with c'^T [e']x = (c' x e')^T
        lead = linalg.cross(c_other, e_other)[:2] @ f_[:2]
        back = f_.T @ c_other
        denominator = float(lead[:2] @ back[:2])
        if denominator == 0:
            return -1.0
        return -float(lead @ c) * float(c @ back) / denominator

    first, second = squared(f, e2, c1, c2), squared(f.T, e1, c2, c1)
    return (
        math.sqrt(first) if first > 0 else None,
        math.sqrt(second) if second > 0 else None,
    )


def assess(
    fundamental: Array,
    e1: Array,
    e2: Array,
    p: Array,
    q: Array,
    *,
    image_size1: tuple[float, float] | None,
    image_size2: tuple[float, float] | None,
) -> Plausibility:
    """All plausibility cues of one candidate geometry.

    Without image sizes the landmarks' bounding box stands in for the photo (its centre for
    the principal point, its long side for the photo's).
    """
    frames = [_frame(points, size) for points, size in ((p, image_size1), (q, image_size2))]
    focals = implied_focal_lengths(fundamental, e1, e2, frames[0][0], frames[1][0])
    low, high = PHONE_FOCAL_RANGE
    phone_like = all(
        focal is not None and low * long_side <= focal <= high * long_side
        for focal, (_, long_side, _) in zip(focals, frames, strict=True)
    )
    inside = sum(
        _inside(epipole, box) for epipole, (_, _, box) in zip((e1, e2), frames, strict=True)
    )
    deviation = sum(
        abs(math.log(focal / (TYPICAL_PHONE_FOCAL * long_side))) if focal is not None else math.inf
        for focal, (_, long_side, _) in zip(focals, frames, strict=True)
    )
    return Plausibility(
        oriented_violations(fundamental, e2, p, q), focals, phone_like, inside, deviation
    )


def _frame(points: Array, size: tuple[float, float] | None) -> tuple[Array, float, Array]:
    """(principal point, long side, [xmin, ymin, xmax, ymax]) of a photo."""
    if size is not None:
        box = np.array([0.0, 0.0, size[0], size[1]])
    else:
        box = np.concatenate([points.min(axis=0), points.max(axis=0)])
    centre = (box[:2] + box[2:]) / 2
    return centre, float(max(box[2] - box[0], box[3] - box[1], 1.0)), box


def _inside(epipole: Array, box: Array) -> bool:
    if abs(epipole[2]) < 1e-12 * linalg.norm(epipole):
        return False
    x, y = epipole[:2] / epipole[2]
    return bool(box[0] <= x <= box[2] and box[1] <= y <= box[3])
