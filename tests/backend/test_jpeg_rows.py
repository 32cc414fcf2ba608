"""A crop decodes only the rows it shows, and shows what a crop of the whole photo shows."""

from __future__ import annotations

from functools import cache
from typing import Any

import cv2
import numpy as np
import pytest
from images import encoded, store
from PIL import Image

from backend.photos.jpeg_rows import row_index
from backend.photos.pictures import crop_around, decode_photo, encode_image


@cache
def noisy_photo(width: int, height: int, grey: bool = False) -> bytes:
    """A stored photo of smooth colour and noise (every MCU row has detail to decode)."""
    rng = np.random.default_rng(width * height)
    ys, xs = np.mgrid[0:height, 0:width]
    smooth = np.stack([xs * 255 // width, ys * 255 // height, (xs + ys) % 256], axis=2)
    pixels = np.clip(smooth + rng.normal(0, 20, smooth.shape), 0, 255).astype(np.uint8)
    image = Image.fromarray(pixels).convert("L") if grey else Image.fromarray(pixels)
    return store(encoded(image, "PNG")).data


SIZES = [(320, 240), (333, 250), (250, 333), (1600, 1200)]


@pytest.mark.parametrize(("width", "height"), SIZES)
def test_a_band_of_a_stored_photo_is_its_rows_bit_for_bit(width: int, height: int) -> None:
    data = noisy_photo(width, height)
    rows = row_index(data)
    assert rows is not None
    assert (rows.width, rows.height) == (width, height)
    whole = decode_photo(data)
    for top, bottom in [(0, 1), (0, 40), (17, 100), (height - 50, height), (height - 1, height)]:
        band, first = rows.band(top, bottom)
        pixels = decode_photo(band)
        assert first <= top
        assert first + pixels.shape[0] >= min(bottom, height)
        assert pixels.shape[0] < height or (top, bottom) == (0, height)  # not the whole photo
        assert np.array_equal(pixels[top - first : bottom - first], whole[top:bottom])


@pytest.mark.parametrize(("width", "height"), SIZES)
def test_a_window_of_a_stored_photo_is_its_pixels_bit_for_bit(width: int, height: int) -> None:
    data = noisy_photo(width, height)
    rows = row_index(data)
    assert rows is not None
    assert rows.interval * rows.frame.mcu_width <= 64  # a few MCUs per segment
    whole = decode_photo(data)
    for top, left in [(0, 0), (17, 33), (height - 50, width - 61), (height // 2, width // 3)]:
        bottom, right = min(top + 50, height), min(left + 61, width)
        part, first, column = rows.window(top, bottom, left, right)
        pixels = decode_photo(part)
        assert first <= top
        assert column <= left
        assert pixels.shape[1] < width or width <= 3 * 64  # not the whole of each row
        shown = pixels[top - first : bottom - first, left - column : right - column]
        assert np.array_equal(shown, whole[top:bottom, left:right])


def test_a_photo_stored_with_a_marker_per_row_is_cropped_by_rows() -> None:
    """Photos stored before the segments: one restart marker per row of MCUs."""
    pixels = decode_photo(noisy_photo(1600, 1200))
    data = encoded(pixels[:, :, ::-1], quality=90, restart_marker_rows=1)
    rows = row_index(data)
    assert rows is not None
    assert rows.per_row == 1
    whole = encode_image(decode_photo(data), format="png")
    for x, y in [(800.5, 600.25), (3.7, 1198.2), (1599, 117)]:
        assert crop_around(data, x, y) == crop_around(whole, x, y)


def test_a_grey_photo_is_stored_with_rows_too() -> None:
    rows = row_index(noisy_photo(200, 150, grey=True))
    assert rows is not None
    assert rows.mcu_rows == 150 // 16 + 1  # stored as RGB: 16 px rows of MCUs


@pytest.mark.parametrize(
    ("x", "y"),
    [(800, 600), (800.5, 600.25), (0, 0), (1600, 1200), (3.7, 1198.2), (1599, 117), (640, 119)],
)
def test_a_crop_of_a_stored_photo_is_the_crop_of_the_whole_photo(x: float, y: float) -> None:
    data = noisy_photo(1600, 1200)
    whole = encode_image(decode_photo(data), format="png")  # lossless: no rows to pick
    assert row_index(whole) is None
    assert crop_around(data, x, y) == crop_around(whole, x, y)


def test_what_is_not_a_stored_photo_has_no_row_index() -> None:
    image = Image.fromarray(np.full((64, 96, 3), 90, np.uint8))

    def jpeg(**options: Any) -> bytes:
        return encoded(image, quality=75, **options)  # PIL's default quality

    assert row_index(jpeg()) is None  # no restart markers
    assert row_index(jpeg(progressive=True, restart_marker_rows=1)) is None
    assert row_index(jpeg(restart_marker_blocks=4)) is None  # markers across rows (6 MCUs)
    assert row_index(jpeg(restart_marker_blocks=2)) is not None  # 3 whole segments a row
    assert row_index(jpeg(restart_marker_rows=1)) is not None
    assert row_index(b"") is None
    assert row_index(b"\xff\xd8\xff") is None
    png = cv2.imencode(".png", np.zeros((8, 8, 3), np.uint8))[1].tobytes()
    assert row_index(png) is None
    cut = jpeg(restart_marker_rows=1)
    assert row_index(cut[: len(cut) // 2]) is None  # truncated: rows missing
