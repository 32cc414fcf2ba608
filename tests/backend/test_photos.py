"""Uploaded photos are stored upright, small enough, metadata-free, and refused cleanly
(backend/photos/intake.py and exif.py).

Every image is made here with PIL (or OpenCV, for what PIL cannot write); nothing is read
from the network. Orientation is checked against the EXIF definitions written out in numpy,
not against PIL's table, which the module itself follows.
"""

from __future__ import annotations

import io
import warnings
from collections.abc import Callable
from functools import cache

import cv2
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from images import (
    assert_shows,
    encoded,
    exif_of,
    pattern,
    png_claiming,
    refused,
    rgb,
    small_photos,
    store,
)
from PIL import ExifTags, Image, ImageCms, JpegImagePlugin, PngImagePlugin

from backend.errors import RefusedError
from backend.photos.intake import StoredPhoto

# A JPEG's segments before its image data that carry pixels only (JFIF header, tables,
# frame, restart interval, scan): anything else (APP1 EXIF/XMP, APP2 ICC, COM, ...) is
# metadata.
PIXEL_SEGMENTS = {0xE0, 0xDB, 0xC0, 0xC4, 0xDD, 0xDA}
REFUSALS = {
    (422, "empty_photo"),
    (415, "unsupported_media_type"),
    (415, "heic_unsupported"),
    (413, "photo_too_large"),
    (422, "invalid_photo"),
}


# --- making and reading images ------------------------------------------------------------


def jpeg_segments(data: bytes) -> list[int]:
    """The markers of a JPEG's segments up to its first scan."""
    assert data[:2] == b"\xff\xd8"
    markers, at = [], 2
    while True:
        assert data[at] == 0xFF
        marker = data[at + 1]
        markers.append(marker)
        if marker == 0xDA:  # start of scan: image data follows
            return markers
        at += 2 + int.from_bytes(data[at + 2 : at + 4], "big")


def jpeg_claiming(width: int, height: int) -> bytes:
    """A JPEG whose frame header says ``width x height`` but whose scan is of 8 x 8 px."""
    data = bytearray(encoded(Image.new("RGB", (8, 8), "red")))
    frame = data.index(b"\xff\xc0")
    data[frame + 5 : frame + 9] = height.to_bytes(2, "big") + width.to_bytes(2, "big")
    return bytes(data)


def halved(image_format: str) -> bytes:
    """The first half of the small photo in ``image_format``."""
    data = small_photos()[image_format]
    return data[: len(data) // 2]


@cache
def phone_photo(width: int = 4032, height: int = 3024) -> bytes:
    """A JPEG (12 MP by default) that compresses like a photo, a noisy gradient at quality
    92 (about 4 MB), with a white 64 px square centred on (3000, 700) px."""
    rng = np.random.default_rng(12)
    gradient = np.add.outer(np.linspace(0, 80, height), np.linspace(0, 70, width))
    noise = rng.integers(0, 30, (height, width, 3), dtype=np.uint8)
    pixels = gradient[:, :, None].astype(np.uint8) + noise
    pixels[700 - 32 : 700 + 32, 3000 - 32 : 3000 + 32] = 255
    return encoded(pixels, quality=92)


# --- what is accepted ---------------------------------------------------------------------


@pytest.mark.parametrize("image_format", ["JPEG", "PNG", "WEBP", "HEIF"])
def test_each_accepted_format_is_stored_as_the_same_pixels_in_jpeg(image_format: str) -> None:
    photo = store(small_photos()[image_format])
    assert photo.data.startswith(b"\xff\xd8\xff")
    assert photo.media_type == "image/jpeg"
    assert (photo.width, photo.height, photo.scale) == (64, 48, 1.0)
    assert_shows(rgb(photo), pattern())


@pytest.mark.parametrize(
    "data",
    [
        encoded(Image.new("RGB", (8, 8)), "GIF"),
        encoded(Image.new("RGB", (8, 8)), "BMP"),
        encoded(Image.new("RGB", (8, 8)), "TIFF"),
        encoded(Image.new("RGB", (8, 8)), "AVIF"),
        b"%PDF-1.7\n",
        b'<svg xmlns="http://www.w3.org/2000/svg"/>',
        b"PK\x03\x04 a zip",
        b"\x00\x00\x00\x18ftypmp42\x00\x00\x00\x00mp42isom",  # a video
        # A generic HEIF brand whose codec is AV1: AVIF in another box.
        b"\x00\x00\x00\x1cftypmif1\x00\x00\x00\x00mif1avifmiaf" + bytes(64),
        b"\xff\xd8",  # too short for JPEG's magic number
    ],
    ids=["gif", "bmp", "tiff", "avif", "pdf", "svg", "zip", "mp4", "mif1-avif", "ffd8"],
)
def test_other_formats_are_refused_naming_what_is_accepted(data: bytes) -> None:
    # PIL here reads GIF, BMP, TIFF and AVIF: refusing them shows the bytes decide, not PIL.
    message = refused(415, "unsupported_media_type", lambda: store(data)).message
    for accepted in ("JPEG", "PNG", "WebP", "HEIC"):
        assert accepted in message


def test_an_empty_upload_is_refused() -> None:
    refused(422, "empty_photo", lambda: store(b""))


def test_a_heic_photo_is_stored_upright_as_jpeg_without_metadata() -> None:
    upright = pattern()
    exif = exif_of(6, GPSLatitude=(52.0, 22.0, 7.5))
    # Given EXIF bytes, pillow-heif writes orientation 6 as the container's rotation (irot),
    # as an iPhone does. The coded pixels are the upright photo turned a quarter anticlockwise.
    data = encoded(np.rot90(upright).copy(), "HEIF", quality=95, exif=exif.tobytes())
    assert data[4:12] == b"ftypheic"
    assert b"irot" in data
    photo = store(data)
    assert (photo.width, photo.height) == (64, 48)
    assert_shows(rgb(photo), upright)
    assert b"Exif" not in photo.data


def test_a_heic_is_turned_by_its_container_not_by_its_exif() -> None:
    # HEIF's irot box decides (libheif applies it; Apple's viewers do the same); an EXIF
    # orientation without one is ignored rather than applied a second time. Given an Exif
    # object, pillow-heif writes the tag without the box.
    data = encoded(pattern(), "HEIF", quality=95, exif=exif_of(6))
    assert b"irot" not in data
    assert_shows(rgb(store(data)), pattern())


@pytest.mark.parametrize(
    "data",
    [
        b"\x00\x00\x00\x18ftypheic\x00\x00\x00\x00mif1heic" + bytes(100),
        b"\x00\x00\x00\x10ftypmif1\x00\x00\x00\x00",
        halved("HEIF"),
    ],
    ids=["garbage-after-ftyp", "only-ftyp", "truncated"],
)
def test_a_heic_that_cannot_be_decoded_asks_for_jpeg(data: bytes) -> None:
    message = refused(415, "heic_unsupported", lambda: store(data)).message
    assert "JPEG" in message
    assert "Most Compatible" in message


# --- what is refused: too large, broken -----------------------------------------------------


@pytest.mark.parametrize("claiming", [png_claiming, jpeg_claiming], ids=["png", "jpeg"])
def test_too_many_pixels_are_refused_from_the_header_before_decoding(
    claiming: Callable[[int, int], bytes],
) -> None:
    # The data holds 8 x 8 px: decoding it as 8000 x 8000 would fail as invalid_photo.
    message = refused(413, "photo_too_large", lambda: store(claiming(8000, 8000))).message
    assert "64 megapixels" in message
    assert "50 megapixels" in message


def test_the_limit_is_the_callers() -> None:
    refused(413, "photo_too_large", lambda: store(small_photos()["PNG"], max_pixels=64 * 48 - 1))
    assert store(small_photos()["PNG"], max_pixels=64 * 48).width == 64


def test_pils_own_decompression_bomb_error_is_a_413_not_a_500() -> None:
    # 400 MP is beyond PIL's error threshold (2 x MAX_IMAGE_PIXELS), raised in Image.open.
    refused(413, "photo_too_large", lambda: store(png_claiming(20_000, 20_000), max_pixels=10**12))


def test_pils_decompression_bomb_warning_is_a_413_when_warnings_are_errors() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error", Image.DecompressionBombWarning)
        data = png_claiming(10_000, 10_000)  # 100 MP: PIL warns (above 89 MP)
        refused(413, "photo_too_large", lambda: store(data, max_pixels=10**12))


@pytest.mark.parametrize(
    "data",
    [
        b"\xff\xd8\xff" + bytes(200),
        b"\x89PNG\r\n\x1a\n" + b"not a chunk" * 20,
        b"RIFF\x10\x00\x00\x00WEBPVP8 " + bytes(50),
        *(halved(image_format) for image_format in ("JPEG", "PNG", "WEBP")),
    ],
    ids=["jpeg", "png", "webp", "JPEG-cut-in-half", "PNG-cut-in-half", "WEBP-cut-in-half"],
)
def test_a_right_magic_number_with_broken_content_is_invalid(data: bytes) -> None:
    refused(422, "invalid_photo", lambda: store(data))


def assert_refused_cleanly(data: bytes) -> None:
    """Stores ``data`` or refuses it with one of the documented RefusedErrors, nothing else."""
    try:
        outcome: StoredPhoto | tuple[int, str] = store(data, max_pixels=1_000_000, max_side=64)
    except RefusedError as error:
        outcome = (error.status, error.code)
    if isinstance(outcome, StoredPhoto):
        assert rgb(outcome).shape == (outcome.height, outcome.width, 3)
    else:
        assert outcome in REFUSALS


@pytest.mark.parametrize("image_format", ["JPEG", "PNG", "WEBP", "HEIF"])
def test_every_truncation_of_a_photo_is_stored_or_refused_cleanly(image_format: str) -> None:
    data = small_photos()[image_format]
    for length in range(0, len(data), max(1, len(data) // 150)):
        assert_refused_cleanly(data[:length])


@settings(max_examples=300, deadline=None, derandomize=True)
@given(
    magic=st.sampled_from(
        [
            b"",
            b"\xff\xd8\xff",
            b"\x89PNG\r\n\x1a\n",
            b"RIFF\x00\x01\x00\x00WEBP",
            b"\x00\x00\x00\x18ftypheic",
            b"\x00\x00\x00\x18ftypmif1",
        ]
    ),
    tail=st.binary(max_size=400),
)
def test_random_bytes_are_refused_cleanly(magic: bytes, tail: bytes) -> None:
    assert_refused_cleanly(magic + tail)


@settings(
    max_examples=300,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(
    image_format=st.sampled_from(["JPEG", "PNG", "WEBP", "HEIF"]),
    changes=st.lists(st.tuples(st.floats(0, 1, exclude_max=True), st.integers(0, 255)), max_size=8),
)
def test_photos_with_corrupted_bytes_are_stored_or_refused_cleanly(
    image_format: str, changes: list[tuple[float, int]]
) -> None:
    data = bytearray(small_photos()[image_format])
    for where, value in changes:
        data[int(where * len(data))] = value
    assert_refused_cleanly(bytes(data))


# --- orientation and metadata ---------------------------------------------------------------

# What the camera coded, for each EXIF orientation, given what a person sees (``upright``):
# TIFF 6.0 / EXIF 2.3 say where the coded 0th row and 0th column are in the visual image.
CODED_FROM_UPRIGHT: dict[int, Callable[[np.ndarray], np.ndarray]] = {
    1: lambda upright: upright,  # row 0 top, column 0 left
    2: lambda upright: upright[:, ::-1],  # row 0 top, column 0 right
    3: lambda upright: upright[::-1, ::-1],  # row 0 bottom, column 0 right
    4: lambda upright: upright[::-1, :],  # row 0 bottom, column 0 left
    5: lambda upright: upright.transpose(1, 0, 2),  # row 0 left, column 0 top
    6: lambda upright: np.rot90(upright, 1),  # row 0 right, column 0 top
    7: lambda upright: upright.transpose(1, 0, 2)[::-1, ::-1],  # row 0 right, column 0 bottom
    8: lambda upright: np.rot90(upright, -1),  # row 0 left, column 0 bottom
}


@pytest.mark.parametrize("orientation", range(1, 9))
def test_every_exif_orientation_is_stored_upright(orientation: int) -> None:
    upright = pattern()
    coded = np.ascontiguousarray(CODED_FROM_UPRIGHT[orientation](upright))
    photo = store(encoded(coded, exif=exif_of(orientation)))
    assert (photo.width, photo.height) == (64, 48)
    assert_shows(rgb(photo), upright)


def test_orientation_6_with_gps_is_stored_upright_with_no_exif_left() -> None:
    upright = pattern()
    gps = {"GPSLatitudeRef": "N", "GPSLatitude": (52.0, 22.0, 7.5)}
    exif = exif_of(6, "PhoneMaker", **gps)  # 6: rotate 90 degrees clockwise to show
    data = encoded(np.rot90(upright).copy(), exif=exif)
    with Image.open(io.BytesIO(data)) as original:  # the upload does hold a position
        assert original.size == (48, 64)
        assert original.getexif().get_ifd(ExifTags.IFD.GPSInfo)[ExifTags.GPS.GPSLatitude]

    photo = store(data)

    assert (photo.width, photo.height) == (64, 48)
    assert_shows(rgb(photo), upright)
    with Image.open(io.BytesIO(photo.data)) as stored:
        assert len(stored.getexif()) == 0
        assert stored.getexif().get_ifd(ExifTags.IFD.GPSInfo) == {}
    assert b"Exif" not in photo.data
    assert b"PhoneMaker" not in photo.data


def test_a_broken_exif_block_leaves_the_photo_as_coded() -> None:
    data = encoded(pattern())
    payload = b"Exif\x00\x00II*\x00\xff\xff\xff\x7f"  # an IFD offset past the end
    broken = data[:2] + b"\xff\xe1" + (len(payload) + 2).to_bytes(2, "big") + payload + data[2:]
    with pytest.warns(UserWarning, match="Corrupt EXIF"):
        photo = store(broken)
    assert_shows(rgb(photo), pattern())


@pytest.mark.parametrize("orientation", [0, 9, 65535])
def test_an_orientation_outside_1_to_8_leaves_the_photo_as_coded(orientation: int) -> None:
    assert_shows(rgb(store(encoded(pattern(), exif=exif_of(orientation)))), pattern())


XMP = (
    b'<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF '
    b'xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"><rdf:Description '
    b'xmlns:exif="http://ns.adobe.com/exif/1.0/" exif:GPSLatitude="52,22.1N"/>'
    b"</rdf:RDF></x:xmpmeta>"
)


@pytest.mark.parametrize("image_format", ["JPEG", "PNG", "WEBP", "HEIF"])
def test_no_metadata_survives(image_format: str) -> None:
    exif = exif_of(make="PhoneMaker", GPSLatitude=(52.0, 22.0, 7.5))
    icc = ImageCms.ImageCmsProfile(ImageCms.createProfile("sRGB")).tobytes()
    extra: dict[str, object] = {"xmp": XMP}
    if image_format == "JPEG":
        extra["comment"] = b"PhoneMaker comment"
    if image_format == "PNG":
        text = PngImagePlugin.PngInfo()
        text.add_itxt("XML:com.adobe.xmp", XMP.decode())
        text.add_text("Comment", "PhoneMaker comment")
        extra = {"pnginfo": text}
    data = encoded(Image.fromarray(pattern()), image_format, exif=exif, icc_profile=icc, **extra)
    assert b"PhoneMaker" in data or image_format == "HEIF"  # HEIF may compress it

    photo = store(data)

    assert set(jpeg_segments(photo.data)) <= PIXEL_SEGMENTS
    for secret in (b"Exif", b"PhoneMaker", b"GPSLatitude", b"adobe", b"ICC_PROFILE"):
        assert secret not in photo.data
    with Image.open(io.BytesIO(photo.data)) as stored:
        assert not {"exif", "xmp", "icc_profile", "comment"} & set(stored.info)


# --- size -------------------------------------------------------------------------------------


def test_a_large_photo_is_downscaled_to_max_side_keeping_aspect_and_places() -> None:
    upright = pattern(block=300)  # 1200 x 900
    photo = store(encoded(upright), max_side=400)
    assert (photo.width, photo.height) == (400, 300)
    assert photo.scale == pytest.approx(1 / 3)
    assert_shows(rgb(photo), pattern(block=100), block=100)


def test_downscaling_follows_the_upright_long_side() -> None:
    upright = pattern(rows=4, columns=3, block=300)  # portrait 900 x 1200, coded landscape
    photo = store(encoded(np.rot90(upright, -1).copy(), exif=exif_of(8)), max_side=400)
    assert (photo.width, photo.height) == (300, 400)
    assert photo.scale == pytest.approx(1 / 3)
    assert_shows(rgb(photo), pattern(rows=4, columns=3, block=100), block=100)


def test_a_small_photo_is_never_upscaled() -> None:
    photo = store(small_photos()["PNG"], max_side=1000)
    assert (photo.width, photo.height, photo.scale) == (64, 48, 1.0)


@pytest.mark.parametrize(
    ("width", "height", "max_side"),
    # 4033 x 3025 decodes at 1/8 as 505 x 379 px of which the last are partial: resizing all
    # of them, not just the photo's part, would move the square by 0.4 px.
    [(4032, 3024, 2560), (4032, 3024, 800), (4033, 3025, 500)],
    ids=["12MP-to-2560", "12MP-to-800-via-draft-quarter", "odd-size-via-draft-eighth"],
)
def test_a_phone_photo_keeps_its_exact_size_and_geometry(
    width: int, height: int, max_side: int
) -> None:
    photo = store(phone_photo(width, height), max_side=max_side)
    scale = max_side / width
    assert (photo.width, photo.height) == (max_side, round(height * scale))
    assert photo.scale == pytest.approx(scale)
    # The white square's centre, found as the centroid of what is brighter than the photo
    # (pixel centres on integers: a centre on a pixel edge e is at e * scale - 0.5). The
    # centroid itself is off by up to 0.15 px (blur of the square on a sloping background).
    brightness = rgb(photo) @ np.array([0.299, 0.587, 0.114])
    weight = np.clip(brightness - 200, 0, None)
    rows, columns = np.indices(weight.shape)
    found = (np.sum(columns * weight) / weight.sum(), np.sum(rows * weight) / weight.sum())
    expected = (3000 * scale - 0.5, 700 * photo.height / height - 0.5)
    assert found == pytest.approx(expected, abs=0.3)


def test_the_stored_jpeg_is_quality_90_and_its_size_is_reported() -> None:
    photo = store(small_photos()["PNG"])
    reference = encoded(Image.fromarray(rgb(photo)), quality=90)
    with (
        Image.open(io.BytesIO(photo.data)) as stored,
        Image.open(io.BytesIO(reference)) as expected,
    ):
        assert stored.size == (photo.width, photo.height)
        assert isinstance(stored, JpegImagePlugin.JpegImageFile)
        assert isinstance(expected, JpegImagePlugin.JpegImageFile)
        assert stored.quantization == expected.quantization
        assert "progressive" not in stored.info


# --- colour modes and animations ------------------------------------------------------------


def half_transparent(mode: str) -> Image.Image:
    """Left half opaque blue (grey in LA), right half fully transparent."""
    image = Image.new("RGBA", (32, 32), (0, 0, 255, 255))
    image.paste((255, 0, 0, 0), (16, 0, 32, 32))
    return image.convert(mode) if mode == "RGBA" else image.convert("LA")


def palette_with_transparent_index() -> Image.Image:
    image = Image.new("P", (32, 32), 0)
    image.putpalette([0, 0, 255, 255, 0, 0])
    image.paste(1, (16, 0, 32, 32))
    image.info["transparency"] = 1
    return image


def sixteen_bit_rgb_png() -> bytes:
    bgr = np.zeros((32, 32, 3), dtype=np.uint16)
    bgr[:, :] = (1000, 0, 40000)
    ok, data = cv2.imencode(".png", bgr)
    assert ok
    return bytes(data.tobytes())


BLUE, WHITE = (0, 0, 255), (255, 255, 255)


@pytest.mark.parametrize(
    ("data", "left", "right"),
    [
        (encoded(Image.new("L", (32, 32), 100)), (100,) * 3, (100,) * 3),
        (encoded(Image.new("CMYK", (32, 32), (0, 255, 255, 0))), (255, 0, 0), (255, 0, 0)),
        (encoded(Image.new("1", (32, 32), 1), "PNG"), WHITE, WHITE),
        (encoded(Image.new("RGB", (32, 32), (0, 200, 0)).convert("P"), "PNG"), (0, 200, 0), None),
        (encoded(palette_with_transparent_index(), "PNG"), BLUE, WHITE),
        (encoded(half_transparent("RGBA"), "PNG"), BLUE, WHITE),
        (encoded(half_transparent("LA"), "PNG"), (29,) * 3, WHITE),
        (encoded(half_transparent("RGBA"), "WEBP", lossless=True), BLUE, WHITE),
        (encoded(Image.fromarray(np.full((32, 32), 40000, np.uint16)), "PNG"), (156,) * 3, None),
        (sixteen_bit_rgb_png(), (156, 0, 3), None),
    ],
    ids=[
        "grey-jpeg",
        "cmyk-jpeg",
        "1-bit-png",
        "palette-png",
        "palette-png-transparent-index",
        "rgba-png",
        "grey-alpha-png",
        "rgba-webp",
        "16-bit-grey-png",
        "16-bit-rgb-png",
    ],
)
def test_every_colour_mode_is_stored_as_8_bit_rgb(
    data: bytes, left: tuple[int, int, int], right: tuple[int, int, int] | None
) -> None:
    pixels = rgb(store(data)).astype(int)  # rgb() checks the mode is RGB
    assert np.abs(pixels[16, 6] - left).max() <= 12, pixels[16, 6]
    assert np.abs(pixels[16, 26] - (right or left)).max() <= 12, pixels[16, 26]


@pytest.mark.parametrize(
    ("image_format", "params"),
    [("WEBP", {"lossless": True}), ("PNG", {}), ("MPO", {})],
    ids=["animated-webp", "apng", "mpo-two-jpegs"],
)
def test_only_the_first_frame_is_stored(image_format: str, params: dict[str, object]) -> None:
    red, blue = Image.new("RGB", (64, 64), "red"), Image.new("RGB", (64, 64), "blue")
    data = encoded(red, image_format, save_all=True, append_images=[blue], **params)
    with Image.open(io.BytesIO(data)) as original:
        # Pillow types n_frames on the formats with frames only, not on what open() returns.
        assert original.n_frames == 2  # type: ignore[attr-defined]
    photo = store(data, max_side=32)  # the MPO goes through JPEG draft mode too
    assert (photo.width, photo.height) == (32, 32)
    assert np.abs(rgb(photo)[16, 16].astype(int) - (255, 0, 0)).max() <= 12
