"""What an upload's EXIF says that the service uses: its orientation and its lens tags.

Read from the upload before its pixels are stored (:mod:`.intake`), which keep none of EXIF
(GPS above all: the stored photo is shown to the other participant).
"""

from __future__ import annotations

import math

from PIL import ExifTags, Image

from .lens import LensFacts


def orientation(image: Image.Image) -> int:
    """EXIF orientation 1-8 of ``image`` (TIFF 6.0, tag 274); 1 (as coded) when absent or
    not one of those.

    PIL reads a corrupt EXIF block as empty (with a warning): such a photo is shown as coded
    rather than refused. HEIF needs none: libheif applies the container's rotation, and
    pillow-heif then resets the EXIF tag to 1.
    """
    value = image.getexif().get(ExifTags.Base.Orientation, 1)
    return value if isinstance(value, int) and 1 <= value <= 8 else 1


def lens_facts(image: Image.Image) -> LensFacts:
    """The lens tags of ``image``'s EXIF (:mod:`.lens` decides what they mean); none when
    absent or not numbers. A corrupt EXIF block reads as empty, as for the orientation."""
    exif = image.getexif()
    details = exif.get_ifd(ExifTags.IFD.Exif)
    return LensFacts(
        focal_35mm=_number(details.get(ExifTags.Base.FocalLengthIn35mmFilm)),
        focal_mm=_number(details.get(ExifTags.Base.FocalLength)),
        make=_text(exif.get(ExifTags.Base.Make)),
        model=_text(exif.get(ExifTags.Base.Model)),
        digital_zoom=_number(details.get(ExifTags.Base.DigitalZoomRatio)),
    )


def _number(value: object) -> float | None:
    try:
        number = float(value)  # type: ignore[arg-type]  # ints and IFDRationals
    except (TypeError, ValueError, ZeroDivisionError):
        return None
    return number if math.isfinite(number) and number > 0 else None


def _text(value: object) -> str | None:
    if isinstance(value, bytes):
        value = value.decode("ascii", "replace")
    if not isinstance(value, str):
        return None
    return value.strip("\x00 ")[:64] or None
