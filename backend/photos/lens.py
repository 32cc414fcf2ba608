"""What a photo says of its lens, as the solver can use it: a 35 mm-equivalent focal length
and how sure it is (docs/geometry.md, "The camera model").

The facts come from EXIF, read by the server from an original upload, or by the phone
before it shrinks the photo (the shrunk copy it sends has none). Only the focal length is
kept: make and model decide how to read it, and are then dropped, like everything else of
EXIF (GPS above all).

``FocalLengthIn35mmFilm`` is the lens as the photo was framed on iPhones: digital zoom
included (an iPhone SE at 1.95x writes 55 mm where its lens is 28 mm). Other makers are
known to write the lens alone and the zoom apart, in ``DigitalZoomRatio``; which one a
photo did cannot be told, so a zoomed non-Apple photo gets a focal length between the two
readings with an uncertainty that spans both. Without the 35 mm figure the focal length in
mm alone says nothing (it needs the sensor's size): the phone prior answers then.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

# EXIF focal lengths are whole millimetres and lenses vary a little (the solver's default).
EXIF_UNCERTAINTY = 0.02
# What a phone's lens can be, 35 mm equivalent: wider or longer is a misreading.
PLAUSIBLE_MM = (10.0, 400.0)

ToldBy = Literal["photo", "phone"]


@dataclass(frozen=True)
class LensFacts:
    """The EXIF tags that describe a photo's lens, as read (None: absent)."""

    focal_35mm: float | None = None  # FocalLengthIn35mmFilm, mm
    focal_mm: float | None = None  # FocalLength, mm (the real lens: informative only)
    make: str | None = None
    model: str | None = None
    digital_zoom: float | None = None  # DigitalZoomRatio (0 or 1: none)


@dataclass(frozen=True)
class Lens:
    """A photo's lens as the solver uses it."""

    focal_35mm: float
    uncertainty: float  # relative standard deviation
    told_by: ToldBy


def lens(facts: LensFacts, told_by: ToldBy) -> Lens | None:
    """The lens these facts give, or None when they give none (the phone prior answers)."""
    focal = facts.focal_35mm
    if focal is None or not math.isfinite(focal):
        return None
    if not PLAUSIBLE_MM[0] <= focal <= PLAUSIBLE_MM[1]:
        return None
    zoom = facts.digital_zoom
    apple = (facts.make or "").strip().lower() == "apple"
    # No zoom, or zoom included (Apple), or a zoom that cannot come on top of this lens (no
    # phone's reaches that far): the focal length as read.
    if (
        zoom is None
        or not math.isfinite(zoom)
        or zoom <= 1.0
        or apple
        or focal * zoom > PLAUSIBLE_MM[1]
    ):
        return Lens(focal, EXIF_UNCERTAINTY, told_by)
    # Zoom included or not: the geometric middle, one log-sd reaching each reading.
    spread = math.log(zoom) / 2.0
    return Lens(focal * math.exp(spread), min(1.0, max(EXIF_UNCERTAINTY, spread)), told_by)
