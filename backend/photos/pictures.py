"""Pictures made from a stored photo: its pixels for drawing on, a drawing's image or layer
bytes, and the crop around a landmark ("find #3").

Pixel coordinates are OpenCV's, as in :mod:`shared_solver.drawing.overlay`: pixel ``(i, j)`` is
centred on ``x = i, y = j``, and a point is on a ``width x height`` photo when
``0 <= x <= width`` and ``0 <= y <= height``.
"""

from __future__ import annotations

import math
from typing import Final, Literal

import cv2
import numpy as np
from numpy.typing import NDArray

from backend.errors import ErrorCode, RefusedError
from shared_solver.drawing.palette import OUTLINE_COLOUR_BGR, Bgr

from .intake import invalid_photo
from .jpeg_rows import RowIndex, row_index

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


def decode_photo(data: bytes) -> NDArray[np.uint8]:
    """(H, W, 3) uint8 BGR pixels of a stored photo, exactly as stored (for OpenCV drawing).

    Raises RefusedError ``invalid_photo`` when ``data`` is not an image.
    """
    buffer = np.frombuffer(data, dtype=np.uint8)
    if buffer.size == 0:
        raise invalid_photo()
    try:
        # Stored photos are upright already; ignoring EXIF keeps pixels where taps are.
        image = cv2.imdecode(buffer, cv2.IMREAD_COLOR_BGR | cv2.IMREAD_IGNORE_ORIENTATION)
    except cv2.error as error:
        raise invalid_photo() from error
    if image is None:
        raise invalid_photo()
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
    stored here only the pixels the crop shows are decoded (:mod:`.jpeg_rows`), the same as
    the whole photo's.

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
    if rows is not None:  # a stored photo: only the pixels the crop shows
        part, first, column = rows.window(top, top + size + 1, left, left + size + 1)
        photo = decode_photo(part)
    else:
        first = column = 0
    # The whole pixels first (grey beyond the photo), one more row and column to
    # interpolate from; then the sub-pixel shift, which a whole-pixel tap does not need.
    window = _window(photo, left - column, top - first, size + 1)
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
