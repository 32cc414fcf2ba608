"""Which way the lens looked when the photo was taken, as the phone's compass read it at the
shutter (the app's own camera; issue 23, "the phone as an instrument").

A heading is the direction of the lens axis seen from above, in degrees clockwise from north
(north 0, east 90), and the reading's standard deviation in degrees. Both phones' norths are
the same (magnetic is fine): the solver uses only the difference of the two headings, and
only beside both photos' gravity. A heading without gravity is kept but unused. Kept with
the photo, replaced with it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from backend.errors import ErrorCode, RefusedError
from shared_solver.validation import FINEST_DEG, LARGEST_HEADING_DEG

# A phone's compass indoors, beside a hall's steel: about 15 degrees (the solver's default).
DEFAULT_SIGMA_DEG = 15.0


@dataclass(frozen=True)
class Heading:
    """A photo's compass reading: ``deg`` clockwise from north in [0, 360), ``sigma_deg``."""

    deg: float
    sigma_deg: float

    @classmethod
    def read(cls, deg: float | None, sigma_deg: float | None) -> Heading | None:
        """The reading as stored (two columns, ``heading`` and ``heading_sigma_deg``), or
        None."""
        if deg is None:
            return None
        return cls(deg, DEFAULT_SIGMA_DEG if sigma_deg is None else sigma_deg)


def heading(deg: float | None, sigma_deg: float | None) -> Heading | None:
    """The heading a phone sent with its photo, wrapped to [0, 360); None when it sent none.

    Raises:
        RefusedError: ``invalid_request`` for a heading that is not a finite number, or a
            sigma beyond what the solver honours.
    """
    if deg is None:
        if sigma_deg is not None:
            raise RefusedError(ErrorCode.INVALID_REQUEST, "heading_sigma_deg needs heading.")
        return None
    if not math.isfinite(deg):
        raise RefusedError(
            ErrorCode.INVALID_REQUEST, "heading must be a finite number of degrees from north."
        )
    sigma = DEFAULT_SIGMA_DEG if sigma_deg is None else sigma_deg
    if not (math.isfinite(sigma) and FINEST_DEG <= sigma <= LARGEST_HEADING_DEG):
        raise RefusedError(
            ErrorCode.INVALID_REQUEST,
            f"heading_sigma_deg must be between {FINEST_DEG:g} and {LARGEST_HEADING_DEG:g} "
            "degrees.",
        )
    # 360 - 1e-14 wraps to 360.0 in floating point: that is north, 0.
    wrapped = math.fmod(deg, 360.0) % 360.0
    return Heading(0.0 if wrapped == 360.0 else wrapped, sigma)
