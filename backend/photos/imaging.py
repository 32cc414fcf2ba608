"""Photos as the service keeps them: upright, downscaled, stripped of metadata, JPEG.

An upload is untrusted bytes from a phone. :func:`store_photo` decides what it is from its
first bytes (never from a file name or a content type), refuses it from its header alone when
it has too many pixels, and decodes it into a fresh 8-bit RGB JPEG that carries no metadata at
all: a phone photo's EXIF may hold where it was taken (GPS), and the stored photo is shown to
the other participant. EXIF orientation is applied first, so the stored pixels are the ones a
browser shows and the participants' taps are in the stored photo's pixels.

Every failure is a :class:`~backend.errors.RefusedError` with a stable code; nothing an upload
holds can make these functions raise anything else.

Pixel coordinates are OpenCV's, as in :mod:`shared_solver.drawing.overlay`: pixel ``(i, j)`` is
centred on ``x = i, y = j``, and a point is on a ``width x height`` photo when
``0 <= x <= width`` and ``0 <= y <= height``.
"""

from __future__ import annotations

import io
import math
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Final, Literal

import cv2
import numpy as np
import pillow_heif
from numpy.typing import NDArray
from PIL import ExifTags, Image, JpegImagePlugin

from backend.errors import ErrorCode, RefusedError
from shared_solver.drawing.palette import OUTLINE_COLOUR_BGR, Bgr

from .jpeg_rows import RowIndex, row_index
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
_DRAWING_JPEG_QUALITY: Final = 88
# zlib level 1: drawings are mostly flat colour, so a higher level saves little and costs time.
_DRAWING_PNG_COMPRESSION: Final = 1

# Where a crop pads beyond the photo: mid grey, which no landmark is mistaken for.
_PAD_GREY: Final = 128
# The cross-hair of a crop: a ring around the point with four ticks, open in the middle so
# the landmark itself stays visible; white over a dark outline reads on any photo.
_RING_RADIUS_PX: Final = 9
_TICK_LENGTH_PX: Final = 7
_RING_COLOUR_BGR: Final[Bgr] = (255, 255, 255)


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
        orientation = _orientation(image)
        lens = _lens_facts(image)
        stored_size, scale = _stored_size(image.size, max_side)
        pixels = _decode_to_size(image, stored_size)
    upright = pixels.transpose(_UPRIGHT[orientation]) if orientation in _UPRIGHT else pixels
    # PIL's JPEG writer takes some metadata (the comment) from ``info`` when not passed;
    # the stored photo keeps none of what came in.
    upright.info = {}
    buffer = io.BytesIO()
    # A restart marker after every row of MCUs: a crop decodes only its rows (.jpeg_rows).
    upright.save(
        buffer, format="JPEG", quality=_STORED_QUALITY, optimize=False, restart_marker_rows=1
    )
    width, height = upright.size
    return StoredPhoto(data=buffer.getvalue(), width=width, height=height, scale=scale, lens=lens)


def decode_photo(data: bytes) -> NDArray[np.uint8]:
    """(H, W, 3) uint8 BGR pixels of a stored photo, exactly as stored (for OpenCV drawing).

    Raises RefusedError ``invalid_photo`` when ``data`` is not an image.
    """
    buffer = np.frombuffer(data, dtype=np.uint8)
    if buffer.size == 0:
        raise _invalid_photo()
    try:
        # Stored photos are upright already; ignoring EXIF keeps pixels where taps are.
        image = cv2.imdecode(buffer, cv2.IMREAD_COLOR_BGR | cv2.IMREAD_IGNORE_ORIENTATION)
    except cv2.error as error:
        raise _invalid_photo() from error
    if image is None:
        raise _invalid_photo()
    return np.ascontiguousarray(image, dtype=np.uint8)


def encode_image(image: NDArray[np.uint8], *, format: Literal["png", "jpeg"]) -> bytes:
    """``image``, (H, W, 3) uint8 BGR, as PNG (lossless) or JPEG (quality 88) bytes.

    Raises ValueError for any other array: drawings are made by the service, so a wrong one
    is a bug, not a request to refuse.
    """
    if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3 or image.size == 0:
        raise ValueError(
            f"encode_image takes an (H, W, 3) uint8 BGR image, not {image.shape} {image.dtype}."
        )
    if format == "jpeg":
        ok, encoded = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, _DRAWING_JPEG_QUALITY])
    else:
        ok, encoded = cv2.imencode(
            ".png", image, [cv2.IMWRITE_PNG_COMPRESSION, _DRAWING_PNG_COMPRESSION]
        )
    if not ok:
        raise ValueError(f"OpenCV could not encode a {image.shape} image as {format}.")
    return bytes(encoded.tobytes())


def encode_layer(drawn: NDArray[np.uint8], photo: NDArray[np.uint8]) -> bytes:
    """PNG of what ``drawn`` adds to ``photo``: the drawing alone, transparent elsewhere.

    Both are (H, W, 3) uint8 BGR of the same shape, ``drawn`` a copy of ``photo`` drawn on.
    A pixel the drawing changed is kept, opaque; every other pixel is transparent black, so
    the PNG of a drawing over a 2560 x 1920 photo is tens of kB where the drawn photo is
    hundreds: a phone that shows its own photo needs only this layer.

    Raises ValueError when the shapes differ or are not (H, W, 3) uint8.
    """
    same = drawn.shape == photo.shape and drawn.dtype == photo.dtype == np.uint8
    if not same or drawn.ndim != 3 or drawn.shape[2] != 3 or drawn.size == 0:
        raise ValueError(
            f"A layer needs two (H, W, 3) uint8 images, not {drawn.shape}, {photo.shape}."
        )
    # OpenCV's whole-image operations: numpy's per-pixel any() and masking took ~0.5 s here.
    blue, green, red = cv2.split(cv2.absdiff(drawn, photo))
    _, alpha = cv2.threshold(cv2.max(cv2.max(blue, green), red), 0, 255, cv2.THRESH_BINARY)
    layer = cv2.merge([*cv2.split(cv2.bitwise_and(drawn, drawn, mask=alpha)), alpha])
    # Mostly zeros: no row filter, and zlib's default level, halve the bytes of the drawings'
    # level 1 in about the same time (~60 ms for 2560 x 1920).
    options = [cv2.IMWRITE_PNG_COMPRESSION, 6, cv2.IMWRITE_PNG_FILTER, cv2.IMWRITE_PNG_FILTER_NONE]
    ok, encoded = cv2.imencode(".png", layer, options)
    if not ok:
        raise ValueError(f"OpenCV could not encode a {layer.shape} layer as PNG.")
    return bytes(encoded.tobytes())


def crop_around(
    data: bytes, x: float, y: float, *, size: int = 240, rows: RowIndex | None = None
) -> bytes:
    """JPEG of the ``size x size`` px of the stored photo ``data`` around ``(x, y)``.

    ``(x, y)`` (stored-photo pixels) lands on pixel ``(size // 2, size // 2)`` of the crop,
    sub-pixel positions included, also near the photo's edges, where the crop is padded with
    grey. A thin white ring with four ticks, open in the middle, marks the point. Of a photo
    stored here only the rows the crop shows are decoded (:mod:`.jpeg_rows`), with the same
    pixels as the whole photo's.

    ``rows``: ``row_index(data)``, when known already.

    Raises RefusedError ``outside_photo`` when the point is not on the photo (or not a number),
    ``invalid_photo`` when ``data`` is not an image; ValueError when ``size`` < 1.
    """
    if size < 1:
        raise ValueError(f"A crop is at least 1 px wide, not {size}.")
    rows = rows or row_index(data)
    if rows is None:  # not a stored photo: all of it
        photo, top = decode_photo(data), 0
        height, width = photo.shape[:2]
    else:
        width, height = rows.width, rows.height
    if not (math.isfinite(x) and math.isfinite(y) and 0 <= x <= width and 0 <= y <= height):
        raise RefusedError(
            ErrorCode.OUTSIDE_PHOTO,
            f"The point ({x:g}, {y:g}) is not on the {width} x {height} px photo; "
            "tap a point on the photo.",
        )
    centre = size // 2
    left, top = math.floor(x) - centre, math.floor(y) - centre  # the crop's first pixel
    if rows is not None:  # a stored photo: only the rows the crop shows
        band, first = rows.band(top, top + size + 1)
        photo = decode_photo(band)
    else:
        first = 0
    # The whole pixels first (grey beyond the photo), one more row and column to
    # interpolate from; then the sub-pixel shift, which a whole-pixel tap does not need.
    window = _window(photo, left, top - first, size + 1)
    shift = np.array([[1.0, 0.0, left - x + centre], [0.0, 1.0, top - y + centre]])
    warped = cv2.warpAffine(
        window,
        shift,
        (size, size),
        flags=cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_CONSTANT,
        borderValue=(_PAD_GREY, _PAD_GREY, _PAD_GREY),
    )
    crop: NDArray[np.uint8] = np.asarray(warped, dtype=np.uint8)
    _draw_crosshair(crop, centre)
    return encode_image(crop, format="jpeg")


def _window(pixels: NDArray[np.uint8], left: int, top: int, side: int) -> NDArray[np.uint8]:
    """(side, side, 3): ``pixels`` from ``(left, top)`` on, grey where they end."""
    height, width = pixels.shape[:2]
    x0, y0 = min(max(left, 0), width), min(max(top, 0), height)
    x1, y1 = max(min(left + side, width), x0), max(min(top + side, height), y0)
    grey = (_PAD_GREY, _PAD_GREY, _PAD_GREY)
    if x1 == x0 or y1 == y0:
        return np.full((side, side, 3), _PAD_GREY, np.uint8)
    below, right = top + side - y1, left + side - x1
    padded = cv2.copyMakeBorder(
        pixels[y0:y1, x0:x1], y0 - top, below, x0 - left, right, cv2.BORDER_CONSTANT, value=grey
    )
    return np.asarray(padded, dtype=np.uint8)


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
        raise _invalid_photo() from error


def _check_pixels(size: tuple[int, int], max_pixels: int) -> None:
    """Refuses a photo of more than ``max_pixels`` from its header's size, before decoding."""
    width, height = size
    if width < 1 or height < 1:
        raise _invalid_photo()
    if width * height > max_pixels:
        raise RefusedError(
            ErrorCode.PHOTO_TOO_LARGE,
            f"This photo is {width} x {height} px ({_megapixels(width * height)} megapixels). "
            + _limit_sentence(max_pixels),
        )


def _orientation(image: Image.Image) -> int:
    """EXIF orientation 1-8 of ``image``; 1 (as coded) when absent or not one of those.

    PIL reads a corrupt EXIF block as empty (with a warning): such a photo is shown as coded
    rather than refused. HEIF needs none: libheif applies the container's rotation, and
    pillow-heif then resets the EXIF tag to 1.
    """
    value = image.getexif().get(ExifTags.Base.Orientation, 1)
    return value if isinstance(value, int) and 1 <= value <= 8 else 1


def _lens_facts(image: Image.Image) -> LensFacts:
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


# --- drawing and errors -------------------------------------------------------------------


def _draw_crosshair(canvas: NDArray[np.uint8], centre: int) -> None:
    """A ring with four outward ticks around pixel ``(centre, centre)``, open in the middle."""
    ends = [
        (
            (centre + dx * _RING_RADIUS_PX, centre + dy * _RING_RADIUS_PX),
            (
                centre + dx * (_RING_RADIUS_PX + _TICK_LENGTH_PX),
                centre + dy * (_RING_RADIUS_PX + _TICK_LENGTH_PX),
            ),
        )
        for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))
    ]
    # The dark outline first, then the white stroke on top of it.
    for colour, thickness in ((OUTLINE_COLOUR_BGR, 3), (_RING_COLOUR_BGR, 1)):
        cv2.circle(canvas, (centre, centre), _RING_RADIUS_PX, colour, thickness, cv2.LINE_AA)
        for start, end in ends:
            cv2.line(canvas, start, end, colour, thickness, cv2.LINE_AA)


def _megapixels(pixels: int) -> str:
    return f"{pixels / 1e6:.3g}"


def _limit_sentence(max_pixels: int) -> str:
    return (
        f"Photos of up to {_megapixels(max_pixels)} megapixels are accepted; "
        "send a smaller one (a phone camera's normal setting is fine)."
    )


def _invalid_photo() -> RefusedError:
    return RefusedError(
        ErrorCode.INVALID_PHOTO,
        "This photo is damaged or incomplete and cannot be read; take or pick it again.",
    )
