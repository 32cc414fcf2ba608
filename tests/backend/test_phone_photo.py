"""What a phone that taps before its upload lands relies on (frontend/src/upload.ts): the
server stores the phone's downscaled photo at the size it was sent, so taps made on the
phone's copy are in the stored photo's pixels; and the answer's drawing comes alone, as a
small transparent layer, since the phone has the photo under it."""

from __future__ import annotations

import io

import cv2
import numpy as np
import pytest
from phones import Phones, landmarks, scene
from PIL import Image

from backend.limits import STORED_PHOTO_SIDE
from testbed.client import Phone


def phone_jpeg(width: int, height: int) -> bytes:
    """A photo as the phone sends it: a canvas's JPEG, no EXIF (downscale.ts)."""
    rng = np.random.default_rng(7)
    pixels = rng.integers(0, 255, (height, width, 3), dtype=np.uint8)
    buffer = io.BytesIO()
    Image.fromarray(pixels).save(buffer, format="JPEG", quality=90)
    return buffer.getvalue()


@pytest.mark.parametrize(
    "size", [(STORED_PHOTO_SIDE, 1920), (1920, STORED_PHOTO_SIDE), (STORED_PHOTO_SIDE, 1153)]
)
def test_the_phones_photo_is_stored_at_the_size_it_was_sent(
    starter: Phone, size: tuple[int, int]
) -> None:
    stored = starter.upload(phone_jpeg(*size))
    assert stored.status_code == 200, stored.text
    assert (stored.json()["width"], stored.json()["height"]) == size
    assert stored.json()["scale"] == 1.0
    photo = starter.call("GET", "/photo/starter")
    assert Image.open(io.BytesIO(photo.content)).size == size


def test_the_answers_layer_is_the_drawing_alone(uploaded: Phones) -> None:
    starter, joiner = uploaded
    s = scene(6)
    starter.tap(landmarks=landmarks(s.landmarks1), friend=list(s.epipole1))
    joiner.tap(landmarks=landmarks(s.landmarks2))
    get = joiner.client.get
    url = joiner.url("/overlay/joiner")
    layer = get(url, params={"layer": "true"}, headers=joiner.auth)
    assert layer.status_code == 200, layer.text
    assert layer.headers["content-type"] == "image/png"
    rgba = cv2.imdecode(np.frombuffer(layer.content, np.uint8), cv2.IMREAD_UNCHANGED)
    assert rgba is not None
    assert rgba.shape == (480, 640, 4)
    drawn = rgba[..., 3] == 255
    assert set(np.unique(rgba[..., 3])) == {0, 255}
    assert 0 < drawn.mean() < 0.5  # a drawing, not a photo
    # Where it is opaque, it is the full overlay's drawing; elsewhere the photo shows.
    full = get(url, params={"format": "png"}, headers=joiner.auth)
    overlay = cv2.imdecode(np.frombuffer(full.content, np.uint8), cv2.IMREAD_COLOR)
    assert overlay is not None
    assert np.array_equal(rgba[..., :3][drawn], overlay[drawn])
    photo = get(joiner.url("/photo/joiner"), headers=joiner.auth)
    pixels = cv2.imdecode(np.frombuffer(photo.content, np.uint8), cv2.IMREAD_COLOR)
    assert pixels is not None
    assert np.array_equal(overlay[~drawn], pixels[~drawn])
    assert len(layer.content) < len(full.content) / 3


def test_a_layer_of_a_non_answer_is_refused(uploaded: Phones) -> None:
    starter, _ = uploaded
    response = starter.call("GET", "/overlay/joiner", params={"layer": "maybe"})
    assert response.status_code == 422
    assert set(response.json()["error"]) == {"code", "message"}
