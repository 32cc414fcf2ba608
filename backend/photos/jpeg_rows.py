"""A band of rows of a stored photo, decoded without decoding the rest of it.

A landmark's crop needs 240 rows of a photo of 1200 or more; decoding all of it took
most of a crop's time. Stored photos are written with a restart marker after every row
of MCUs (JPEG's 8 or 16 px blocks of rows: ITU-T T.81, B.2.4.4 and F.1.2.3): the
entropy-coded data between two markers is one row of MCUs that decodes on its own (each
restart resets the DC predictions). A band of rows is then a JPEG of its own, made of the
photo's header with the band's height, and those rows' data with their markers numbered
afresh; decoding it costs what its rows cost.

Its pixels are the photo's, bit for bit, but at the band's top and bottom edges, where the
decoder's chroma upsampling has no row beyond to blend with: :meth:`RowIndex.band` reaches
half an MCU further than the rows asked for, except at the photo's own edges.

A JPEG without a restart marker per MCU row (written elsewhere, or before stored photos
had them), progressive, arithmetic-coded or not a JPEG: :func:`row_index` says None, and
the caller decodes all of it.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

_SOI, _EOI = b"\xff\xd8", b"\xff\xd9"
# Huffman-coded baseline and extended sequential: one scan carries every row.
_SEQUENTIAL = frozenset({0xC0, 0xC1})
_OTHER_FRAMES = frozenset({0xC2, 0xC3, *range(0xC5, 0xC8), *range(0xC9, 0xCC), *range(0xCD, 0xD0)})
_DRI, _SOS = 0xDD, 0xDA
_RESTART = re.compile(rb"\xff[\xd0-\xd7]")


@dataclass(frozen=True)
class _Frame:
    """What a frame header (SOF) says: its size, its MCU, its components."""

    height_at: int  # offset of its height field in the file
    width: int
    height: int
    mcu_width: int
    mcu_height: int
    components: int


@dataclass(frozen=True)
class RowIndex:
    """Where each row of MCUs of a stored JPEG is, found without decoding it."""

    data: bytes
    frame: _Frame
    rows: list[tuple[int, int]]  # each MCU row's entropy-coded bytes: (start, end)

    @property
    def width(self) -> int:
        return self.frame.width

    @property
    def height(self) -> int:
        return self.frame.height

    def band(self, top: int, bottom: int) -> tuple[bytes, int]:
        """A JPEG of the photo's rows ``top`` to ``bottom`` (exclusive; clipped to the
        photo), exactly as in the whole photo, and the photo row its first row is: whole
        MCU rows, reaching half an MCU beyond the rows asked for."""
        step = self.frame.mcu_height
        first = min(max(0, (top - step // 2) // step), len(self.rows) - 1)
        last = max(min(len(self.rows), math.ceil((bottom + step // 2) / step)), first + 1)
        height = min(self.height, last * step) - first * step
        header = bytearray(self.data[: self.rows[0][0]])  # up to the scan's data
        at = self.frame.height_at
        header[at : at + 2] = height.to_bytes(2, "big")
        parts = [bytes(header)]
        for number, (start, end) in enumerate(self.rows[first:last]):
            if number:
                parts.append(bytes((0xFF, 0xD0 + (number - 1) % 8)))
            parts.append(self.data[start:end])
        parts.append(_EOI)
        return b"".join(parts), first * step


def row_index(data: bytes) -> RowIndex | None:
    """The rows of MCUs of ``data``, a sequential JPEG with a restart marker after each row
    of MCUs; None for anything else."""
    if not data.startswith(_SOI):
        return None
    at = len(_SOI)
    frame: _Frame | None = None
    interval = 0
    while at + 4 <= len(data) and data[at] == 0xFF:
        marker = data[at + 1]
        length = int.from_bytes(data[at + 2 : at + 4], "big")
        segment = data[at + 4 : at + 2 + length]
        if marker in _OTHER_FRAMES:
            return None
        if marker in _SEQUENTIAL:
            frame = _frame(segment, height_at=at + 5)
        elif marker == _DRI and len(segment) >= 2:
            interval = int.from_bytes(segment[:2], "big")
        elif marker == _SOS:
            scanned = segment[0] if segment else 0
            if frame is None or scanned != frame.components:  # not every component: progressive
                return None
            return _indexed(data, at + 2 + length, frame, interval)
        at += 2 + length
    return None


def _frame(segment: bytes, height_at: int) -> _Frame | None:
    if len(segment) < 6:
        return None
    height = int.from_bytes(segment[1:3], "big")
    width = int.from_bytes(segment[3:5], "big")
    components = segment[5]
    factors = segment[6 : 6 + 3 * components]
    if not (width and height and components) or len(factors) != 3 * components:
        return None
    horizontal = max(factors[1 + 3 * i] >> 4 for i in range(components))
    vertical = max(factors[1 + 3 * i] & 0x0F for i in range(components))
    if components == 1:  # one component: 8 x 8 blocks whatever its factors say
        horizontal = vertical = 1
    return _Frame(height_at, width, height, 8 * horizontal, 8 * vertical, components)


def _indexed(data: bytes, entropy_at: int, frame: _Frame, interval: int) -> RowIndex | None:
    """The index, if the scan from ``entropy_at`` has a restart marker per row of MCUs."""
    end = data.find(_EOI, entropy_at)  # entropy-coded data has no 0xFF 0xD9
    if interval != math.ceil(frame.width / frame.mcu_width) or end < entropy_at:
        return None
    starts, ends = [entropy_at], []
    for restart in _RESTART.finditer(data, entropy_at, end):
        ends.append(restart.start())
        starts.append(restart.end())
    ends.append(end)
    if len(starts) != math.ceil(frame.height / frame.mcu_height):
        return None
    return RowIndex(data, frame, list(zip(starts, ends, strict=True)))
