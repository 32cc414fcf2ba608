"""The colours of every drawing of the answer: the photo overlay and the phone app.

Landmark ``k`` (the number people see, from 1) is painted ``LANDMARK_COLOURS_HEX[(k - 1) % 12]``
on both phones, so "the orange 3" means the same spot in both photos. The table is written
once, in ``palette.json``, as web colours ``"#rrggbb"`` (RGB order); OpenCV's BGR tuples are
derived from it.

The colours are bright enough to read with a dark outline on dark photos and on bright ones,
and none is the friend's yellow or the suspect red, which mean something else.
"""

from __future__ import annotations

import json
from pathlib import Path

Bgr = tuple[int, int, int]

# The one source, which the phone app reads too (frontend/src/palette.ts and its CSS).
_PALETTE = json.loads(Path(__file__).with_name("palette.json").read_text())

LANDMARK_COLOURS_HEX: tuple[str, ...] = tuple(c["hex"] for c in _PALETTE["landmarks"])
# The friend (marker, region, arrow, curve) and a landmark to re-check.
FRIEND_COLOUR_HEX: str = _PALETTE["friend"]
SUSPECT_COLOUR_HEX: str = _PALETTE["suspect"]
# Outline under every stroke and letter, so colours read on bright photos too.
OUTLINE_COLOUR_HEX: str = _PALETTE["outline"]
# How much of the friend's colour a curve's band lays over the photo.
BAND_OPACITY: float = _PALETTE["band_opacity"]


def hex_to_bgr(colour: str) -> Bgr:
    """``"#rrggbb"`` -> ``(b, g, r)``, the order OpenCV draws in."""
    value = int(colour.removeprefix("#"), 16)
    return value & 0xFF, (value >> 8) & 0xFF, value >> 16


LANDMARK_COLOURS_BGR: tuple[Bgr, ...] = tuple(hex_to_bgr(c) for c in LANDMARK_COLOURS_HEX)
FRIEND_COLOUR_BGR = hex_to_bgr(FRIEND_COLOUR_HEX)
SUSPECT_COLOUR_BGR = hex_to_bgr(SUSPECT_COLOUR_HEX)
OUTLINE_COLOUR_BGR = hex_to_bgr(OUTLINE_COLOUR_HEX)


def landmark_colour(label: int) -> Bgr:
    """BGR colour of landmark number ``label`` (1-based; the palette repeats every 12)."""
    return LANDMARK_COLOURS_BGR[(label - 1) % len(LANDMARK_COLOURS_BGR)]


def landmark_colour_hex(label: int) -> str:
    """Web colour ``"#rrggbb"`` of landmark ``label``: the same as :func:`landmark_colour`."""
    return LANDMARK_COLOURS_HEX[(label - 1) % len(LANDMARK_COLOURS_HEX)]
