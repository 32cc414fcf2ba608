"""Which way was down when the photo was taken, as the phone's sensors read it at the
shutter (the app's own camera; docs/geometry.md, "Gravity at the shutter").

A unit vector in the stored photo's camera frame (x right along its rows, y down its
columns, z out of the lens) and the reading's standard deviation per axis, in degrees. With
both photos' readings the solver needs no landmark for the friend's level and one for a
point. Kept with the photo, replaced with it; nothing else of the sensors is kept.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

from backend.errors import ErrorCode, RefusedError
from shared_solver.validation import FINEST_DEG, LARGEST_DEG

# A phone's accelerometer at rest: about a degree (the solver's default).
DEFAULT_SIGMA_DEG = 1.0


@dataclass(frozen=True)
class Gravity:
    """A photo's gravity reading: ``down`` (3,) unit, ``sigma_deg`` per axis."""

    down: tuple[float, float, float]
    sigma_deg: float

    def as_json(self) -> str:
        return json.dumps([*self.down, self.sigma_deg])

    @classmethod
    def read(cls, stored: str | None) -> Gravity | None:
        """The reading as stored (``as_json``), or None."""
        if stored is None:
            return None
        x, y, z, sigma = json.loads(stored)
        return cls((float(x), float(y), float(z)), float(sigma))


def gravity(down: list[float] | None, sigma_deg: float | None) -> Gravity | None:
    """The reading a phone sent with its photo, checked; None when it sent none.

    Raises:
        RefusedError: ``invalid_request`` for a reading that is no direction (three finite
            numbers, not all zero) or a sigma beyond what the solver honours.
    """
    if down is None:
        if sigma_deg is not None:
            raise RefusedError(ErrorCode.INVALID_REQUEST, "gravity_sigma_deg needs gravity.")
        return None
    if len(down) != 3 or not all(math.isfinite(value) for value in down):
        raise RefusedError(
            ErrorCode.INVALID_REQUEST, "gravity must be three finite numbers: x, y, z."
        )
    size = math.sqrt(sum(value * value for value in down))
    if not size > 0.0:
        raise RefusedError(ErrorCode.INVALID_REQUEST, "gravity must not be all zero.")
    sigma = DEFAULT_SIGMA_DEG if sigma_deg is None else sigma_deg
    if not (math.isfinite(sigma) and FINEST_DEG <= sigma <= LARGEST_DEG):
        raise RefusedError(
            ErrorCode.INVALID_REQUEST,
            f"gravity_sigma_deg must be between {FINEST_DEG:g} and {LARGEST_DEG:g} degrees.",
        )
    x, y, z = (value / size for value in down)
    return Gravity((x, y, z), sigma)
