"""Images made for the photo tests: a pattern of distinct colours in each accepted format,
stored as the service stores an upload, compared block by block, and a refusal checked
(made with PIL; nothing is read from the network)."""

from __future__ import annotations

import io
import zlib
from collections.abc import Callable
from functools import cache
from typing import Any

import numpy as np
import pillow_heif
import pytest
from PIL import ExifTags, Image

from backend.errors import RefusedError
from backend.photos.intake import StoredPhoto, store_photo

pillow_heif.register_heif_opener()

MAX_PIXELS = 50_000_000
MAX_SIDE = 2560
BLOCK = 16
# Twelve colours far apart in at least one channel, one per block of the test pattern.
COLOURS = np.array(
    [
        [255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0],
        [255, 0, 255], [0, 255, 255], [0, 0, 0], [255, 255, 255],
        [128, 0, 0], [0, 128, 0], [0, 0, 128], [128, 128, 128],
    ],
    dtype=np.uint8,
)  # fmt: skip
# JPEG rounding and chroma subsampling move a block centre's colour by a few levels, far
# less than the distance between two colours of the pattern.
COLOUR_TOLERANCE = 40


def pattern(rows: int = 3, columns: int = 4, block: int = BLOCK) -> np.ndarray:
    """(rows * block, columns * block, 3) RGB: a grid of distinct colours, no symmetry."""
    indices = np.arange(rows * columns).reshape(rows, columns) % len(COLOURS)
    return np.kron(COLOURS[indices], np.ones((block, block, 1), dtype=np.uint8))


def encoded(image: Image.Image | np.ndarray, image_format: str = "JPEG", **params: Any) -> bytes:
    if isinstance(image, np.ndarray):
        image = Image.fromarray(image)
    if image_format == "JPEG":
        params.setdefault("quality", 95)
    buffer = io.BytesIO()
    image.save(buffer, format=image_format, **params)
    return buffer.getvalue()


def exif_of(orientation: int | None = None, make: str | None = None, **gps: object) -> Image.Exif:
    """EXIF as a phone writes it: an ``orientation`` and a ``make`` if given, and GPS tags
    (``gps`` by their names in ``ExifTags.GPS``)."""
    exif = Image.Exif()
    if orientation is not None:
        exif[ExifTags.Base.Orientation] = orientation
    if make is not None:
        exif[ExifTags.Base.Make] = make
    for name, value in gps.items():
        exif.get_ifd(ExifTags.IFD.GPSInfo)[ExifTags.GPS[name]] = value
    return exif


def store(data: bytes, **limits: int) -> StoredPhoto:
    return store_photo(
        data,
        max_pixels=limits.get("max_pixels", MAX_PIXELS),
        max_side=limits.get("max_side", MAX_SIDE),
    )


def refused(status: int, code: str, call: Callable[[], object]) -> RefusedError:
    with pytest.raises(RefusedError) as caught:
        call()
    assert (caught.value.status, caught.value.code) == (status, code), caught.value.message
    assert caught.value.message[0].isupper()
    assert caught.value.message.endswith(".")
    return caught.value


def rgb(photo: StoredPhoto | bytes) -> np.ndarray:
    data = photo.data if isinstance(photo, StoredPhoto) else photo
    with Image.open(io.BytesIO(data)) as image:
        assert image.mode == "RGB"
        return np.asarray(image)


def assert_shows(actual: np.ndarray, expected: np.ndarray, block: int = BLOCK) -> None:
    """``actual`` has ``expected``'s shape and the colour of each of its blocks (at their
    centres)."""
    assert actual.shape == expected.shape
    centres = (slice(block // 2, None, block),) * 2
    difference = np.abs(actual[centres].astype(int) - expected[centres].astype(int)).max(axis=2)
    # The blocks (row, column) whose colour is not shown, if any.
    assert difference.max() < COLOUR_TOLERANCE, np.argwhere(difference >= COLOUR_TOLERANCE)


def png_claiming(width: int, height: int) -> bytes:
    """A PNG whose header says ``width x height`` but whose data is that of 8 x 8 px."""
    data = bytearray(encoded(Image.new("RGB", (8, 8), "red"), "PNG"))
    ihdr = data.index(b"IHDR")
    data[ihdr + 4 : ihdr + 12] = width.to_bytes(4, "big") + height.to_bytes(4, "big")
    crc = zlib.crc32(bytes(data[ihdr : ihdr + 17]))
    data[ihdr + 17 : ihdr + 21] = crc.to_bytes(4, "big")
    return bytes(data)


@cache
def small_photos() -> dict[str, bytes]:
    """One small photo of each accepted format (the HEIC with real HEVC data)."""
    image = Image.fromarray(pattern())
    return {
        "JPEG": encoded(image),
        "PNG": encoded(image, "PNG"),
        "WEBP": encoded(image, "WEBP", quality=90),
        "HEIF": encoded(image, "HEIF", quality=90),
    }
