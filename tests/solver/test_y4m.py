"""The YUV4MPEG2 writer the fake camera's videos come from (testbed/y4m.py): the header
Chromium reads, I420 planes of video-range BT.601, every frame in order."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from testbed.y4m import read_luma, write_y4m

SIZE = (48, 32)  # (width, height) px: even, and not square (rows and columns not swapped)


def frame(rng: np.random.Generator) -> np.ndarray:
    """(32, 48, 3) uint8 BGR: a gradient (every level of grey) under noise."""
    width, height = SIZE
    ramp = np.linspace(0.0, 255.0, width * height).reshape(height, width, 1)
    noisy = ramp + rng.normal(0.0, 20.0, (height, width, 3))
    return np.clip(noisy, 0, 255).astype(np.uint8)


def test_the_luma_read_back_is_the_frames_grey_in_video_range(
    tmp_path: Path, rng: np.random.Generator
) -> None:
    frames = [frame(rng), frame(rng)]
    path = tmp_path / "two.y4m"
    write_y4m(path, frames, fps=5)
    assert path.read_bytes().startswith(b"YUV4MPEG2 W48 H32 F5:1 Ip A1:1 C420jpeg\nFRAME\n")
    lumas = read_luma(path)
    assert len(lumas) == 2
    for luma, written in zip(lumas, frames, strict=True):
        assert luma.shape == (32, 48)
        # BT.601 luma (OpenCV's grey), squeezed into video's 16-235.
        grey = cv2.cvtColor(written, cv2.COLOR_BGR2GRAY).astype(np.float64)
        assert np.abs(luma - (16 + grey * 219 / 255)).max() <= 1.0
    assert not np.array_equal(lumas[0], lumas[1])


def test_the_colours_come_back(tmp_path: Path) -> None:
    """A frame of flat colour patches 8 px wide decodes to itself (I420 halves the chroma's
    resolution, so flat patches on even pixels lose nothing but rounding)."""
    patches = np.array([[0, 0, 255], [0, 255, 0], [255, 0, 0], [40, 180, 220], [128, 128, 128]])
    width, height = SIZE
    colours = np.repeat(patches, 8, axis=0)[np.arange(width) % 40]
    picture = np.broadcast_to(colours, (height, width, 3)).astype(np.uint8)
    path = tmp_path / "colours.y4m"
    write_y4m(path, [picture])
    planes = np.frombuffer(path.read_bytes()[-width * height * 3 // 2 :], np.uint8)
    decoded = cv2.cvtColor(planes.reshape(height * 3 // 2, width), cv2.COLOR_YUV2BGR_I420)
    assert np.abs(decoded.astype(int) - picture).max() <= 3


@pytest.mark.parametrize(
    "frames",
    [
        [],
        [np.zeros((32, 47, 3), np.uint8)],
        [np.zeros((32, 48, 3), np.uint8), np.zeros((34, 48, 3), np.uint8)],
        [np.zeros((32, 48), np.uint8)],
        [np.zeros((32, 48, 3), np.float32)],
    ],
    ids=["none", "odd width", "two sizes", "grey", "float"],
)
def test_what_is_no_i420_video_is_refused(tmp_path: Path, frames: list[np.ndarray]) -> None:
    with pytest.raises(ValueError, match="frame"):
        write_y4m(tmp_path / "no.y4m", frames)
