"""What is known about the camera that took a photo, as a prior on its focal length.

A phone photo is not an arbitrary projective camera: its pixels are square, its skew is zero,
and its principal point is the image centre to within a fraction of a percent (an offset of
1 % of the diagonal moves the image like a turn of about half a degree, which the fitted
rotation absorbs; docs/geometry.md). What remains unknown is the focal length, and that is a
prior here:

* ``known_focal``: a 35 mm-equivalent focal length (EXIF ``FocalLengthIn35mmFilm``), known to
  a few percent;
* ``phone``: nothing known but that it is a phone. The main camera is about 26 mm, but people
  zoom across a stadium (2x, 3x, 5x) and phones have ultra-wide lenses, so the prior is broad
  in log focal. Measured on facing phones, the friend's position hardly depends on the focal
  length, so a broad prior costs almost nothing in accuracy and keeps the region honest on
  zoomed photos (docs/geometry.md, "Zoomed photos");
* ``unknown``: no camera model at all, the projective geometry of the paper.

Focal lengths are converted with the photo's diagonal, which is what "35 mm equivalent"
means for any aspect ratio, so downscaling and portrait or landscape do not matter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from ..errors import Reason
from ..refusal import SolverError

# The diagonal of a 36 x 24 mm film frame: the reference of "35 mm equivalent".
FILM_DIAGONAL_MM = math.hypot(36.0, 24.0)
# A phone's main camera, 35 mm equivalent (iPhone 26 mm, Pixel 25-27 mm, Galaxy 23-24 mm).
MAIN_CAMERA_MM = 26.0
# Log-focal standard deviation of the phone prior: a factor of e^0.5 = 1.65 either way, so
# 2x zoom and the ultra-wide are 1.4 sigma off and 3x 2.2 sigma (docs/geometry.md).
PHONE_LOG_SIGMA = 0.5
# EXIF focal lengths are whole millimetres and lenses vary a little: 2 % by default.
KNOWN_FOCAL_UNCERTAINTY = 0.02
# No focal length is known to better than a millionth: below it the prior's information
# (1 / uncertainty^2) swamps the fit's normal equations, or overflows.
FINEST_FOCAL_UNCERTAINTY = 1e-6

CameraKind = Literal["unknown", "phone", "known_focal"]


class Camera(BaseModel):
    """What is known about the camera of one photo (``solve(camera1=..., camera2=...)``)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    kind: CameraKind = Field(
        "unknown",
        description="'phone': a phone's camera, focal length unknown (a broad prior); "
        "'known_focal': its 35 mm-equivalent focal length is known; 'unknown': any projective "
        "camera (no model).",
    )
    focal_35mm: float | None = Field(
        None,
        gt=0.0,
        le=2000.0,
        description="35 mm-equivalent focal length in mm (EXIF FocalLengthIn35mmFilm); "
        "required for 'known_focal'.",
    )
    focal_uncertainty: float = Field(
        KNOWN_FOCAL_UNCERTAINTY,
        ge=FINEST_FOCAL_UNCERTAINTY,
        le=1.0,
        description="Relative standard deviation of focal_35mm (0.02 = 2 %).",
    )

    @model_validator(mode="after")
    def _focal_given_when_known(self) -> Camera:
        if (self.kind == "known_focal") != (self.focal_35mm is not None):
            raise ValueError("focal_35mm is given exactly when kind is 'known_focal'")
        return self

    @classmethod
    def phone(cls) -> Camera:
        """A phone photo with no EXIF: the broad phone prior."""
        return cls(kind="phone")

    @classmethod
    def with_focal(cls, focal_35mm: float, uncertainty: float = KNOWN_FOCAL_UNCERTAINTY) -> Camera:
        """A photo whose 35 mm-equivalent focal length is known (from EXIF)."""
        return cls(kind="known_focal", focal_35mm=focal_35mm, focal_uncertainty=uncertainty)


@dataclass(frozen=True)
class FocalPrior:
    """A log-normal prior on one photo's focal length in pixels, and the photo's centre.

    Attributes:
        log_focal: mean of ln(focal / px).
        log_sigma: standard deviation of ln(focal).
        centre: (x, y) principal point, px: the image centre.
        source: the camera kind it came from.
    """

    log_focal: float
    log_sigma: float
    centre: tuple[float, float]
    source: CameraKind

    @property
    def focal_px(self) -> float:
        """The prior's median focal length, px."""
        return math.exp(self.log_focal)


def focal_px(focal_35mm: float, size: tuple[float, float]) -> float:
    """Focal length in px of a photo of ``size`` (width, height) from its 35 mm equivalent."""
    return focal_35mm / FILM_DIAGONAL_MM * math.hypot(*size)


def focal_35mm(focal: float, size: tuple[float, float]) -> float:
    """The 35 mm-equivalent focal length (mm) of ``focal`` px on a photo of ``size``."""
    return focal * FILM_DIAGONAL_MM / math.hypot(*size)


def focal_prior(camera: Camera, size: tuple[float, float]) -> FocalPrior | None:
    """The prior of a camera on a photo of ``size`` (width, height) px; None if ``unknown``.

    Raises:
        SolverError: the focal length in px is not a usable number (a photo size or focal
            length so extreme that it under- or overflows).
    """
    if camera.kind == "unknown":
        return None
    focal = camera.focal_35mm if camera.kind == "known_focal" else MAIN_CAMERA_MM
    assert focal is not None
    pixels = focal_px(focal, size)
    if not (math.isfinite(pixels) and pixels > 0.0 and math.isfinite(math.hypot(*size))):
        raise SolverError(Reason.UNUSABLE_FOCAL)
    sigma = camera.focal_uncertainty if camera.kind == "known_focal" else PHONE_LOG_SIGMA
    return FocalPrior(math.log(pixels), sigma, (size[0] / 2.0, size[1] / 2.0), camera.kind)
