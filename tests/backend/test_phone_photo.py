"""What a phone that taps before its upload lands relies on (frontend/src/upload.ts): the
server stores the phone's downscaled photo at the size it was sent, so taps made on the
phone's copy are in the stored photo's pixels; and the answer's drawing comes alone, as a
small transparent layer, since the phone has the photo under it."""

from __future__ import annotations

import io

import cv2
import numpy as np
import pytest
from images import encoded
from phones import Phones, image_of, scene, tapped_scene
from PIL import Image

from backend.limits import STORED_PHOTO_SIDE
from testbed.client import Phone


def phone_jpeg(width: int, height: int) -> bytes:
    """A photo as the phone sends it: a canvas's JPEG, no EXIF (downscale.ts)."""
    rng = np.random.default_rng(7)
    return encoded(rng.integers(0, 255, (height, width, 3), dtype=np.uint8), quality=90)


@pytest.mark.parametrize(
    "size", [(STORED_PHOTO_SIDE, 1920), (1920, STORED_PHOTO_SIDE), (STORED_PHOTO_SIDE, 1153)]
)
def test_the_phones_photo_is_stored_at_the_size_it_was_sent(
    starter: Phone, size: tuple[int, int]
) -> None:
    stored = starter.uploaded(phone_jpeg(*size))
    assert (stored["width"], stored["height"], stored["scale"]) == (*size, 1.0)
    photo = starter.call("GET", "/photo/starter")
    assert Image.open(io.BytesIO(photo.content)).size == size


def test_the_answers_layer_is_the_drawing_alone(uploaded: Phones) -> None:
    joiner = uploaded[1]
    tapped_scene(*uploaded, scene(6))
    layer = joiner.call("GET", "/overlay/joiner", params={"layer": "true"})
    assert layer.headers["content-type"] == "image/png"
    rgba = image_of(layer, cv2.IMREAD_UNCHANGED)
    assert rgba.shape == (480, 640, 4)
    drawn = rgba[..., 3] == 255
    assert set(np.unique(rgba[..., 3])) == {0, 255}
    assert 0 < drawn.mean() < 0.5  # a drawing, not a photo
    # Where it is opaque, it is the full overlay's drawing; elsewhere the photo shows.
    full = joiner.call("GET", "/overlay/joiner", params={"format": "png"})
    overlay = image_of(full)
    assert np.array_equal(rgba[..., :3][drawn], overlay[drawn])
    pixels = image_of(joiner.call("GET", "/photo/joiner"))
    assert np.array_equal(overlay[~drawn], pixels[~drawn])
    assert len(layer.content) < len(full.content) / 3


def test_a_layer_of_a_non_answer_is_refused(uploaded: Phones) -> None:
    starter, _ = uploaded
    response = starter.call("GET", "/overlay/joiner", params={"layer": "maybe"})
    assert response.status_code == 422
    assert set(response.json()["error"]) == {"code", "message"}
