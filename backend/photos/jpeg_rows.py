"""A window of a stored photo, decoded without decoding the rest of it.

A landmark's crop needs 240 x 240 px of a photo of 1600 x 1200 or more; decoding all of
it took most of a crop's time. Stored photos are written with restart markers that cut
each row of MCUs (JPEG's 8 or 16 px blocks: ITU-T T.81, B.2.4.4 and F.1.2.3) into whole
segments of a few MCUs (:func:`restart_interval`; older ones: one segment per row): the
entropy-coded data between two markers decodes on its own (each restart resets the DC
predictions). A window of whole segments is then a JPEG of its own, made of the photo's
header with the window's size, and those segments' data with their markers numbered afresh;
decoding it costs what its pixels cost.

Its pixels are the photo's, bit for bit, but at the window's edges, where the decoder's
chroma upsampling has no pixel beyond to blend with: :meth:`RowIndex.window` reaches half an
MCU further than the pixels asked for, except at the photo's own edges.

A JPEG whose restart intervals do not cut every row of MCUs into whole segments (written
elsewhere, or without markers), progressive, arithmetic-coded or not a JPEG:
:func:`row_index` says None, and the caller decodes all of it.
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

    height_at: int  # offset of its height field in the file (the width's follows)
    width: int
    height: int
    mcu_width: int
    mcu_height: int
    components: int

    @property
    def columns(self) -> int:
        """MCUs in a row."""
        return math.ceil(self.width / self.mcu_width)


def restart_interval(width: int, mcu_width: int = 16, widest: int = 4) -> int:
    """The restart interval (MCUs) a stored photo ``width`` px wide is written with: the
    largest divisor of its MCUs per row up to ``widest`` (64 px segments at 16 px MCUs,
    about 1 % more bytes), so that a crop decodes a few segments of each row; a whole row
    when no divisor but 1 is that small (a marker per MCU would cost ~10 % more bytes)."""
    columns = math.ceil(width / mcu_width)
    interval = max(d for d in range(1, widest + 1) if columns % d == 0)
    return columns if interval == 1 else interval


@dataclass(frozen=True)
class RowIndex:
    """Where each segment of each row of MCUs of a stored JPEG is, found without decoding
    it."""

    data: bytes
    frame: _Frame
    interval: int  # MCUs per segment: the photo's restart interval
    segments: list[tuple[int, int]]  # each segment's entropy-coded bytes, row by row

    @property
    def width(self) -> int:
        return self.frame.width

    @property
    def height(self) -> int:
        return self.frame.height

    @property
    def per_row(self) -> int:
        return self.frame.columns // self.interval

    @property
    def mcu_rows(self) -> int:
        return len(self.segments) // self.per_row

    def band(self, top: int, bottom: int) -> tuple[bytes, int]:
        """A JPEG of the photo's rows ``top`` to ``bottom`` (exclusive; clipped to the
        photo), all of their width, and the photo row its first row is."""
        band, first, _ = self.window(top, bottom, 0, self.width)
        return band, first

    def window(self, top: int, bottom: int, left: int, right: int) -> tuple[bytes, int, int]:
        """A JPEG of the photo's pixels in rows ``top`` to ``bottom`` and columns ``left`` to
        ``right`` (exclusive; clipped to the photo), exactly as in the whole photo, and the
        photo row and column its first pixel is: whole segments, reaching half an MCU beyond
        the pixels asked for."""
        step, wide = self.frame.mcu_height, self.frame.mcu_width
        first = min(max(0, (top - step // 2) // step), self.mcu_rows - 1)
        last = max(min(self.mcu_rows, math.ceil((bottom + step // 2) / step)), first + 1)
        span = wide * self.interval  # px of a segment
        start = min(max(0, (left - wide // 2) // span), self.per_row - 1)
        end = max(min(self.per_row, math.ceil((right + wide // 2) / span)), start + 1)
        height = min(self.height, last * step) - first * step
        width = min(self.width, end * span) - start * span
        header = bytearray(self.data[: self.segments[0][0]])  # up to the scan's data
        at = self.frame.height_at
        header[at : at + 4] = height.to_bytes(2, "big") + width.to_bytes(2, "big")
        parts = [bytes(header)]
        number = 0
        for row in range(first * self.per_row, last * self.per_row, self.per_row):
            for start_at, end_at in self.segments[row + start : row + end]:
                if number:
                    parts.append(bytes((0xFF, 0xD0 + (number - 1) % 8)))
                parts.append(self.data[start_at:end_at])
                number += 1
        parts.append(_EOI)
        return b"".join(parts), first * step, start * span


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
    """The index, if the scan from ``entropy_at`` has restart markers that cut each row of
    MCUs into whole segments."""
    end = data.find(_EOI, entropy_at)  # entropy-coded data has no 0xFF 0xD9
    if interval < 1 or frame.columns % interval or end < entropy_at:
        return None
    starts, ends = [entropy_at], []
    for restart in _RESTART.finditer(data, entropy_at, end):
        ends.append(restart.start())
        starts.append(restart.end())
    ends.append(end)
    rows = math.ceil(frame.height / frame.mcu_height)
    if len(starts) != rows * (frame.columns // interval):
        return None
    return RowIndex(data, frame, interval, list(zip(starts, ends, strict=True)))
