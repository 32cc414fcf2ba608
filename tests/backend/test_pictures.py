"""What is made from a stored photo (backend/photos/pictures.py): its pixels, a drawing's
bytes, and the crop around a landmark, placed exactly and refused off the photo."""

from __future__ import annotations

import math
from functools import cache

import cv2
import numpy as np
import pytest
from images import assert_shows, pattern, refused, small_photos, store

from backend.photos.pictures import crop_around, decode_photo, encode_image


def test_decode_photo_gives_bgr_pixels_as_stored() -> None:
    photo = store(small_photos()["PNG"])
    pixels = decode_photo(photo.data)
    assert pixels.shape == (48, 64, 3)
    assert pixels.dtype == np.uint8
    assert_shows(pixels[:, :, ::-1], pattern())


@pytest.mark.parametrize("data", [b"", b"not a photo", b"\xff\xd8\xff" + bytes(50)])
def test_decode_photo_refuses_what_is_not_an_image(data: bytes) -> None:
    refused(422, "invalid_photo", lambda: decode_photo(data))


def test_encode_image_writes_lossless_png_and_jpeg() -> None:
    bgr = np.ascontiguousarray(pattern()[:, :, ::-1])
    png = encode_image(bgr, format="png")
    assert png.startswith(b"\x89PNG\r\n\x1a\n")
    decoded = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    assert decoded is not None
    assert np.array_equal(decoded, bgr)
    jpeg = encode_image(bgr, format="jpeg")
    assert jpeg.startswith(b"\xff\xd8\xff")
    assert_shows(decode_photo(jpeg)[:, :, ::-1], pattern())


@pytest.mark.parametrize(
    "image",
    [np.zeros((4, 4), np.uint8), np.zeros((4, 4, 4), np.uint8), np.zeros((4, 4, 3), np.float32)],
    ids=["grey", "bgra", "float"],
)
def test_encode_image_refuses_what_is_not_a_bgr_image(image: np.ndarray) -> None:
    with pytest.raises(ValueError, match="uint8 BGR"):
        encode_image(image, format="png")


RED_BGR = (0, 0, 255)


@cache
def photo_with_marks() -> bytes:
    """A stored 320 x 200 photo, dark blue-grey, with red 5 x 5 px marks centred on
    (200, 50), (2, 2) and (317, 197); lossless, so a crop's pixels can be checked exactly."""
    bgr = np.full((200, 320, 3), (90, 60, 40), dtype=np.uint8)
    for x, y in ((200, 50), (2, 2), (317, 197)):
        bgr[max(y - 2, 0) : y + 3, max(x - 2, 0) : x + 3] = RED_BGR
    return encode_image(bgr, format="png")


def crop_pixels(x: float, y: float, size: int = 240) -> np.ndarray:
    crop = crop_around(photo_with_marks(), x, y, size=size)
    assert crop.startswith(b"\xff\xd8\xff")
    return decode_photo(crop).astype(int)


def test_a_crop_is_centred_on_the_point_and_marks_it_without_hiding_it() -> None:
    crop = crop_pixels(200, 50)
    assert crop.shape == (240, 240, 3)
    assert np.abs(crop[120, 120] - RED_BGR).max() <= 30  # the point itself is visible
    assert np.abs(crop[120, 160] - (90, 60, 40)).max() <= 12  # photo beyond the ring
    ring = crop[120, 120 - 12 : 120 + 13].max(axis=1)  # along a row through the centre
    assert ring.max() >= 200  # the white ring and ticks cross it


@pytest.mark.parametrize(("x", "y"), [(2, 2), (317, 197), (0, 0), (320, 200)])
def test_a_crop_at_the_edge_keeps_the_point_centred_and_pads_with_grey(x: float, y: float) -> None:
    crop = crop_pixels(x, y, size=100)
    assert crop.shape == (100, 100, 3)
    if (x, y) in ((2, 2), (317, 197)):
        assert np.abs(crop[50, 50] - RED_BGR).max() <= 30
    corner = crop[:10, :10] if x < 160 else crop[90:, 90:]  # beyond the photo
    assert np.abs(corner - 128).max() <= 6


def test_a_crop_keeps_sub_pixel_positions() -> None:
    # A ramp 2 grey levels per px: a point half a pixel off shows as one level.
    ramp = np.repeat(np.arange(0, 256, 2, dtype=np.uint8)[None, :, None], 128, axis=0)
    data = encode_image(np.repeat(ramp, 3, axis=2), format="png")
    crop = decode_photo(crop_around(data, 50.5, 64, size=120)).astype(float)
    assert crop[90:110, 60].mean() == pytest.approx(101, abs=0.4)  # below the ticks


@pytest.mark.parametrize(
    ("x", "y"),
    [(-0.5, 10), (10, -1), (320.5, 10), (10, 201), (math.nan, 10), (10, math.inf)],
)
def test_a_point_off_the_photo_is_refused(x: float, y: float) -> None:
    refused(422, "outside_photo", lambda: crop_around(photo_with_marks(), x, y))
