"""The photos the phone picks: the temple as the test data has it (640 x 480 PNG), and a
12 MP JPEG as a phone's camera gives one, made from it."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
TEMPLE = ROOT / "tests" / "data" / "temple" / "templeSR0006.png"
# A phone's main camera: 12 MP, 4032 x 3024; its JPEGs weigh a few MB (this one 2.5 MB).
PHONE_SIZE = (4032, 3024)
PHONE_QUALITY = 92
GRAIN = 6.0  # sensor noise, sd in grey levels: an enlarged photo alone compresses unlike one


def phone_photo(folder: Path, seed: int) -> Path:
    """The temple enlarged to a 12 MP phone photo with a sensor's grain, saved as a JPEG
    (EXIF-less: the app assumes the lens)."""
    temple = cv2.imread(str(TEMPLE), cv2.IMREAD_COLOR)
    assert temple is not None, TEMPLE
    enlarged = cv2.resize(temple, PHONE_SIZE, interpolation=cv2.INTER_CUBIC).astype(np.float32)
    grain = np.random.default_rng(seed).normal(0.0, GRAIN, size=enlarged.shape)
    photo = np.clip(enlarged + grain, 0, 255).astype(np.uint8)
    path = folder / "phone-12mp.jpg"
    cv2.imwrite(str(path), photo, [cv2.IMWRITE_JPEG_QUALITY, PHONE_QUALITY])
    return path


# The photos: the command line's name -> the report's.
NAMES = {"temple": "temple PNG 640 x 480", "12mp": "12 MP JPEG 4032 x 3024"}


def photo(name: str, folder: Path, seed: int) -> Path:
    """The file of the photo the command line calls ``name`` (one of :data:`NAMES`)."""
    return TEMPLE if name == "temple" else phone_photo(folder, seed)
