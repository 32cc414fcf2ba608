"""Photos as a YUV4MPEG2 video, the file Chromium's fake camera plays
(``--use-fake-device-for-media-stream --use-file-for-fake-video-capture=FILE.y4m``).

The format (https://wiki.multimedia.cx/index.php/YUV4MPEG2): one header line
``YUV4MPEG2 W<width> H<height> F<num>:<den> Ip A1:1 C420jpeg``, then per frame the line
``FRAME`` and the frame's planes, I420: the full-size luma (Y) plane, then the two chroma
planes (U, V) at half the width and half the height, 8 bits each, row by row. Chromium's
reader (``media/capture/video/file_video_capture_device.cc``) takes I420 only, reads the
header from the file's first 200 bytes, plays the frames in a loop and uses the size and
the frame rate (a whole number of frames per second); it ignores the pixel aspect and
fudges the chroma siting.

OpenCV's ``COLOR_BGR2YUV_I420`` makes the planes (BT.601, luma 16-235 as video has it,
which is what Chromium assumes of a file that says nothing of its colours).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np

from .textures import Image

# A whole number of frames per second (Chromium divides the two numbers as integers).
# One frame shown over and over needs no more than a few; fewer cost the browser less.
FRAMES_PER_SECOND = 5


def write_y4m(path: Path, frames: Sequence[Image], fps: int = FRAMES_PER_SECOND) -> None:
    """Write ``frames`` ((H, W, 3) uint8 BGR, all one size, W and H even) to ``path`` as
    an I420 YUV4MPEG2 video at ``fps`` frames per second.

    Raises:
        ValueError: no frame, frames of different sizes, an odd side or not 8-bit BGR.
    """
    if not frames:
        raise ValueError("a video needs at least one frame")
    height, width = frames[0].shape[:2]
    for frame in frames:
        if frame.shape != (height, width, 3) or frame.dtype != np.uint8:
            raise ValueError(f"frames must all be ({height}, {width}, 3) uint8 BGR")
    if width % 2 or height % 2:
        raise ValueError(f"a frame's sides must be even (I420 halves both): {width} x {height}")
    header = f"YUV4MPEG2 W{width} H{height} F{fps}:1 Ip A1:1 C420jpeg\n"
    with path.open("wb") as file:
        file.write(header.encode("ascii"))
        for frame in frames:
            file.write(b"FRAME\n")
            # (H * 3 / 2, W): Y, then U and V, each a quarter of Y, packed.
            file.write(cv2.cvtColor(frame, cv2.COLOR_BGR2YUV_I420).tobytes())


def read_luma(path: Path) -> list[Image]:
    """The luma planes ((H, W) uint8) of the frames of an I420 YUV4MPEG2 video written by
    :func:`write_y4m` (frame lines without parameters)."""
    data = path.read_bytes()
    header, _, body = data.partition(b"\n")
    tags = {tag[:1]: tag[1:] for tag in header.split()[1:]}
    width, height = int(tags[b"W"]), int(tags[b"H"])
    frame_bytes = len(b"FRAME\n") + width * height * 3 // 2
    frames = []
    for start in range(0, len(body), frame_bytes):
        frame = body[start : start + frame_bytes]
        if not frame.startswith(b"FRAME\n") or len(frame) != frame_bytes:
            raise ValueError(f"{path}: a frame at byte {start} is cut short or not a frame")
        luma = np.frombuffer(frame, np.uint8, width * height, offset=len(b"FRAME\n"))
        frames.append(luma.reshape(height, width))
    return frames
