"""Finding a landmark in the other photo once an answer exists (pure numpy and OpenCV).

Every landmark one phone has tapped and the other has not lies on a known epipolar line
in the other photo. This package gives:

- the **band** (:func:`epipolar_band`): that line widened by its uncertainty (from
  ``SolveResult.fundamental_covariance``, which ``solve(..., fundamental_covariance=True)``
  returns, and the tap's precision), clipped to the photo,
  as the phone draws it (:meth:`Band.shape`);
- a **suggestion** (:func:`suggest`): the tapped spot's patch searched along the band by
  template matching in epipolar coordinates, offered only when the match is sure;
- a **check** of a tap in the other photo (:meth:`Band.check`): far outside the band, the
  landmark does not fit the others.

:func:`guide_landmark` does the first two from a ``SolveResult``. Apart from landmarks,
:mod:`.reanchor` matches a frame of a phone's live view to its photo: how the phone has
turned since the shutter (the live view's "Show me").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..projective import Array
from ..result import SolveResult
from .band import FLAG_SIGMAS, LEVEL, Band, BandShape, TapCheck, epipolar_band
from .epipolar import Epipolar
from .polar import Image
from .suggestion import RULES, LandmarkSearch, Rules, Suggestion, suggest

__all__ = [
    "FLAG_SIGMAS",
    "LEVEL",
    "RULES",
    "Band",
    "BandShape",
    "Epipolar",
    "Guide",
    "LandmarkSearch",
    "Rules",
    "Suggestion",
    "TapCheck",
    "epipolar_band",
    "guide_landmark",
    "suggest",
]


@dataclass(frozen=True)
class Guide:
    """What the phone that still has to find a landmark is shown."""

    band: Band
    suggestion: Suggestion | None


def guide_landmark(
    result: SolveResult,
    photo1: Image,
    photo2: Image,
    point: Array,
    *,
    tapped_in: Literal[1, 2],
    tap_sigma: float,
    landmarks1: Array,
    landmarks2: Array,
    search: bool = True,
) -> Guide | None:
    """The band, and a suggestion, for a landmark tapped at ``point`` in one photo only.

    Args:
        result: the current answer, from ``solve(..., fundamental_covariance=True)``.
        photo1, photo2: the stored photos, (H, W, 3) uint8 BGR.
        point: (2,) where the landmark was tapped, px of photo ``tapped_in``.
        tapped_in: the photo it was tapped in; the band is in the other one.
        tap_sigma: the tap's standard deviation, px per axis.
        landmarks1, landmarks2: (N, 2) the landmarks both photos share (those the answer
            used), which say on which side of the other friend the landmark must be.
        search: False for the band alone (no image work).

    Returns:
        None when the answer gives no band (no uncertainty of F: not asked for, the plane
        model, the curve of four landmarks, several candidates) or the band misses the
        other photo.
    """
    epipolar = Epipolar.from_result(
        result, tapped_in=tapped_in, landmarks1=landmarks1, landmarks2=landmarks2
    )
    if epipolar is None:
        return None
    photo_a, photo_b = (photo1, photo2) if tapped_in == 1 else (photo2, photo1)
    height, width = photo_b.shape[:2]
    tapped = np.asarray(point, float)
    covariance = tap_sigma**2 * np.eye(2)
    band = epipolar_band(epipolar, tapped, image_size=(width, height), point_covariance=covariance)
    if band is None:
        return None
    if not search:
        return Guide(band, None)
    sought = LandmarkSearch(photo_a, photo_b, tapped, epipolar, band, point_covariance=covariance)
    return Guide(band, suggest(sought))
