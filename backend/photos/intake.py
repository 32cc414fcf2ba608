"""An upload made into the photo the service keeps: upright, downscaled, stripped of
metadata, JPEG.

An upload is untrusted bytes from a phone. :func:`store_photo` decides what it is from its
first bytes (never from a file name or a content type), refuses it from its header alone when
it has too many pixels, and decodes it into a fresh 8-bit RGB JPEG that carries no metadata at
all: a phone photo's EXIF may hold where it was taken (GPS), and the stored photo is shown to
the other participant. EXIF orientation (:mod:`.exif`) is applied first, so the stored pixels
are the ones a browser shows and the participants' taps are in the stored photo's pixels.

Every failure is a :class:`~backend.errors.RefusedError` with a stable code; nothing an upload
holds can make these functions raise anything else.
"""

from __future__ import annotations

import io
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Final, Literal

import numpy as np
import pillow_heif
from PIL import Image, JpegImagePlugin

from backend.errors import ErrorCode, RefusedError

from . import exif
from .jpeg_rows import restart_interval
from .lens import LensFacts

# Registers the "HEIF" format with PIL (a global registry, so once, at import).
pillow_heif.register_heif_opener()

_Format = Literal["JPEG", "PNG", "WEBP", "HEIF"]

_PNG_MAGIC: Final = b"\x89PNG\r\n\x1a\n"
# ISO-BMFF brands of HEIF images coded with HEVC (what iPhones write), and the generic
# still-image / sequence brands. AVIF shares the container but needs an AV1 decoder the
# service does not promise, so it is refused rather than accepted where libheif has one.
_HEIF_BRANDS: Final = frozenset({b"heic", b"heix", b"hevc", b"hevx", b"heim", b"heis"})
_GENERIC_HEIF_BRANDS: Final = frozenset({b"mif1", b"msf1"})
_AVIF_BRANDS: Final = frozenset({b"avif", b"avis"})

_ACCEPTED: Final = "Send the photo as JPEG, PNG, WebP or HEIC/HEIF."

# The transposition that makes an image upright, by EXIF orientation (TIFF 6.0, tag 274): the
# table of PIL's ImageOps.exif_transpose, applied here after downscaling because transposing
# the 2.5 MP stored photo is cheaper than transposing the 12 MP original.
_UPRIGHT: Final = {
    2: Image.Transpose.FLIP_LEFT_RIGHT,
    3: Image.Transpose.ROTATE_180,
    4: Image.Transpose.FLIP_TOP_BOTTOM,
    5: Image.Transpose.TRANSPOSE,
    6: Image.Transpose.ROTATE_270,
    7: Image.Transpose.TRANSVERSE,
    8: Image.Transpose.ROTATE_90,
}

# PIL's BILINEAR, when it shrinks, is a triangle filter as wide as the output pixel
# (antialiased, not point sampling). Shrinking a 4032 x 3024 zone plate to 2560 x 1920 it
# aliases least of PIL's filters (rms 16 grey levels beyond the new Nyquist; LANCZOS 19,
# BICUBIC 21, BOX 59) and is a little softer (rms 7 in the passband; LANCZOS 1), in 100 ms
# where LANCZOS takes 200 ms: LANCZOS alone would spend most of a 12 MP upload's 300 ms budget.
_DOWNSCALE_FILTER: Final = Image.Resampling.BILINEAR
_STORED_QUALITY: Final = 90


@dataclass(frozen=True)
class StoredPhoto:
    """A photo as stored and shown: upright, metadata-free, 8-bit sRGB JPEG.

    ``width`` and ``height`` are those of the JPEG in ``data``. ``scale`` is the stored long
    side over the uploaded (upright) long side, 1.0 when the photo was small enough already;
    the short side is rounded to whole pixels, so it may differ from ``scale`` by 0.5 px.
    """

    data: bytes
    width: int
    height: int
    scale: float
    media_type: str = "image/jpeg"
    # What the upload's EXIF said of its lens (read, not stored with the pixels).
    lens: LensFacts = field(default_factory=LensFacts)


def store_photo(data: bytes, *, max_pixels: int, max_side: int) -> StoredPhoto:
    """The uploaded ``data`` as the service stores it, or a :class:`RefusedError`.

    Accepts JPEG, PNG, WebP and HEIC/HEIF, recognised by their magic numbers. Refuses photos
    of more than ``max_pixels`` pixels from their header, before decoding. The stored photo
    is upright (EXIF orientation applied), at most ``max_side`` px on its long side (never
    enlarged), RGB without alpha (transparency shows white), the first frame of an
    animation, and carries no EXIF, GPS, XMP, ICC profile or comment.

    Raises RefusedError: ``empty_photo``; ``unsupported_media_type`` (not one of the formats
    above); ``heic_unsupported`` (a HEIC/HEIF that cannot be decoded here);
    ``photo_too_large``; ``invalid_photo`` (corrupt or truncated).
    """
    photo_format = _sniff(data)
    with _refusing_undecodable(photo_format, max_pixels):
        image = Image.open(io.BytesIO(data), formats=[photo_format])
        _check_pixels(image.size, max_pixels)
        orientation = exif.orientation(image)
        lens = exif.lens_facts(image)
        stored_size, scale = _stored_size(image.size, max_side)
        pixels = _decode_to_size(image, stored_size)
    upright = pixels.transpose(_UPRIGHT[orientation]) if orientation in _UPRIGHT else pixels
    # PIL's JPEG writer takes some metadata (the comment) from ``info`` when not passed;
    # the stored photo keeps none of what came in.
    upright.info = {}
    buffer = io.BytesIO()
    # Restart markers that cut each row of MCUs (16 px, 4:2:0) into segments of a few: a
    # crop decodes only the segments it shows (.jpeg_rows).
    upright.save(
        buffer,
        format="JPEG",
        quality=_STORED_QUALITY,
        optimize=False,
        subsampling="4:2:0",
        restart_marker_blocks=restart_interval(upright.size[0]),
    )
    width, height = upright.size
    return StoredPhoto(data=buffer.getvalue(), width=width, height=height, scale=scale, lens=lens)


def invalid_photo() -> RefusedError:
    """The refusal of bytes that are not a readable image (``invalid_photo``)."""
    return RefusedError(
        ErrorCode.INVALID_PHOTO,
        "This photo is damaged or incomplete and cannot be read; take or pick it again.",
    )


# --- recognising the upload -------------------------------------------------------------


def _sniff(data: bytes) -> _Format:
    """The format ``data`` starts like, by magic number; refuses empty and unknown data."""
    if not data:
        raise RefusedError(
            ErrorCode.EMPTY_PHOTO, "The photo is empty (0 bytes); take or pick it again."
        )
    if data.startswith(b"\xff\xd8\xff"):
        return "JPEG"
    if data.startswith(_PNG_MAGIC):
        return "PNG"
    if data[:4] == b"RIFF" and data[8:12] == b"WEBP":
        return "WEBP"
    if _is_heif(data):
        return "HEIF"
    raise RefusedError(
        ErrorCode.UNSUPPORTED_MEDIA_TYPE, f"This file is not a photo we can read. {_ACCEPTED}"
    )


def _is_heif(data: bytes) -> bool:
    """Whether ``data`` opens with the ISO-BMFF ``ftyp`` box of a HEIF image that is not AVIF."""
    if data[4:8] != b"ftyp":
        return False
    major = data[8:12]
    if major in _HEIF_BRANDS:
        return True
    if major not in _GENERIC_HEIF_BRANDS:
        return False
    # mif1/msf1 say "some HEIF"; the compatible brands say which codec. AVIF lists avif.
    box_end = min(int.from_bytes(data[:4], "big"), len(data))
    compatible = {data[at : at + 4] for at in range(16, box_end - 3, 4)}
    return not (compatible & _AVIF_BRANDS) or bool(compatible & _HEIF_BRANDS)


# --- decoding -----------------------------------------------------------------------------


@contextmanager
def _refusing_undecodable(photo_format: _Format, max_pixels: int) -> Iterator[None]:
    """Turns whatever decoding ``photo_format`` raises into the refusal a user can act on."""
    try:
        yield
    except RefusedError:
        raise
    except (Image.DecompressionBombError, Image.DecompressionBombWarning) as error:
        # PIL's own guard runs in Image.open, before the size reaches _check_pixels: an error
        # above 2 x MAX_IMAGE_PIXELS (179 MP), and above MAX_IMAGE_PIXELS a warning, which
        # raises when warnings are errors. Either way the photo is too large, not broken.
        pil_limit = Image.MAX_IMAGE_PIXELS or max_pixels
        if isinstance(error, Image.DecompressionBombError):
            pil_limit *= 2
        limit = min(max_pixels, pil_limit)
        raise RefusedError(
            ErrorCode.PHOTO_TOO_LARGE, f"This photo has too many pixels. {_limit_sentence(limit)}"
        ) from error
    except Exception as error:
        # PIL, its plugins and libheif report broken data as OSError, SyntaxError, ValueError,
        # EOFError, struct.error, IndexError, ...: no list is complete, and every one of them
        # means the same to the user. RefusedError is re-raised above, so limits stay limits.
        if photo_format == "HEIF":
            raise RefusedError(
                ErrorCode.HEIC_UNSUPPORTED,
                "This HEIC/HEIF photo cannot be read here. Send it as JPEG instead: on an "
                'iPhone, set Settings > Camera > Formats to "Most Compatible", or share '
                "the photo as JPEG.",
            ) from error
        raise invalid_photo() from error


def _check_pixels(size: tuple[int, int], max_pixels: int) -> None:
    """Refuses a photo of more than ``max_pixels`` from its header's size, before decoding."""
    width, height = size
    if width < 1 or height < 1:
        raise invalid_photo()
    if width * height > max_pixels:
        raise RefusedError(
            ErrorCode.PHOTO_TOO_LARGE,
            f"This photo is {width} x {height} px ({_megapixels(width * height)} megapixels). "
            + _limit_sentence(max_pixels),
        )


def _stored_size(size: tuple[int, int], max_side: int) -> tuple[tuple[int, int], float]:
    """(width, height) to store a ``size`` photo at, long side at most ``max_side``, and the
    scale (stored long side / original long side)."""
    width, height = size
    long_side = max(width, height)
    if long_side <= max_side:
        return size, 1.0
    scale = max_side / long_side
    return (max(1, round(width * scale)), max(1, round(height * scale))), scale


def _decode_to_size(image: Image.Image, size: tuple[int, int]) -> Image.Image:
    """The first frame of lazily opened ``image``, as 8-bit RGB, resampled to ``size``."""
    box: tuple[float, float, float, float] | None = None
    # libjpeg can decode at 1/2, 1/4 or 1/8 scale directly, for a fraction of the time;
    # draft picks the smallest that is still at least ``size``. MPO (a JPEG with more
    # images after it, from some phones) is a JpegImageFile too. HEIF's draft would pick an
    # embedded thumbnail, smaller and coded worse than the photo: not used.
    if isinstance(image, JpegImagePlugin.JpegImageFile) and size != image.size:
        drafted = image.draft("RGB", size)
        if drafted is not None:
            # The part of the reduced image that is the photo (its last pixels may be partial).
            box = drafted[1]
    image.load()
    rgb = _to_rgb(image)
    if rgb.size == size and box is None:
        return rgb
    return rgb.resize(size, _DOWNSCALE_FILTER, box=box)


def _to_rgb(image: Image.Image) -> Image.Image:
    """``image`` as 8-bit RGB: transparency composited on white, 16-bit grey scaled down."""
    if image.mode == "RGB":
        return image
    if image.mode.startswith("I"):
        # 16-bit grey (PNG) opens as I;16 or I. PIL's convert clips it at 255 rather than
        # scaling, which would turn most of the photo white.
        levels = np.asarray(image).astype(np.int64)
        grey = np.clip(levels >> 8, 0, 255).astype(np.uint8)
        return Image.fromarray(grey).convert("RGB")
    if image.mode in ("RGBA", "LA", "PA", "RGBa", "La") or "transparency" in image.info:
        rgba = image.convert("RGBA")
        white = Image.new("RGB", rgba.size, "white")
        white.paste(rgba, mask=rgba.getchannel("A"))
        return white
    # L, P, 1, CMYK (PIL's conversion ignores an ICC profile; colours are close enough to find
    # a landmark), YCbCr, ...
    return image.convert("RGB")


# --- refusals -----------------------------------------------------------------------------


def _megapixels(pixels: int) -> str:
    return f"{pixels / 1e6:.3g}"


def _limit_sentence(max_pixels: int) -> str:
    return (
        f"Photos of up to {_megapixels(max_pixels)} megapixels are accepted; "
        "send a smaller one (a phone camera's normal setting is fine)."
    )
