"""What ``solve`` was asked, checked: the taps with their precisions, the photos, the cameras."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

from .. import validation
from ..estimation.camera import Camera, FocalPrior, focal_prior
from ..estimation.taps import Taps


@dataclass(frozen=True)
class Request:
    """Validated input of :func:`..solve.solve`.

    Attributes:
        taps: landmarks and the friends' marks, each with its covariance.
        size1, size2: (width, height) of the photos, px, when given.
        labels: the numbers people see on the landmarks.
        cameras: what is known about photo 1's and photo 2's camera.
        with_fundamental_covariance: whether the answer carries F's covariance.
    """

    taps: Taps
    size1: tuple[float, float] | None
    size2: tuple[float, float] | None
    labels: list[int]
    cameras: tuple[Camera, Camera]
    with_fundamental_covariance: bool = False

    def without_gravity(self) -> Request:
        """The same request without the phones' gravity readings (nor their headings, which
        need them)."""
        return replace(self, taps=replace(self.taps, gravity=None, heading=None))

    def without_heading(self) -> Request:
        """The same request without the phones' compass headings."""
        return replace(self, taps=replace(self.taps, heading=None))

    @functools.cached_property
    def sigma(self) -> float:
        """The typical landmark tap's standard deviation, px (reported with the answer)."""
        return self.taps.typical_sigma

    @property
    def diagonal2(self) -> float:
        """Photo 2's diagonal in px (the landmarks' extent when its size is unknown)."""
        if self.size2 is not None:
            return math.hypot(*self.size2)
        return validation.spread(self.taps.q)

    @functools.cached_property
    def priors(self) -> tuple[FocalPrior, FocalPrior] | None:
        """Both photos' focal priors, or None unless both cameras have a model (and sizes)."""
        if self.size1 is None or self.size2 is None:
            return None
        first, second = (
            focal_prior(self.cameras[0], self.size1),
            focal_prior(self.cameras[1], self.size2),
        )
        if first is None or second is None:
            return None
        return first, second
