"""The colours of every drawing of the answer: the photo overlay and, later, the phone app.

Landmark ``k`` (the number people see, from 1) is painted ``LANDMARK_COLOURS_HEX[(k - 1) % 12]``
on both phones, so "the orange 3" means the same spot in both photos. The table is written
once, as web colours ``"#rrggbb"`` (RGB order); OpenCV's BGR tuples are derived from it.

The colours are bright enough to read with a dark outline on dark photos and on bright ones,
and none is the friend's yellow or the suspect red, which mean something else.
"""

from __future__ import annotations

Bgr = tuple[int, int, int]

LANDMARK_COLOURS_HEX: tuple[str, ...] = (
    "#3cb44b",  # green
    "#4d7cff",  # blue
    "#ff8c1a",  # orange
    "#33e0ff",  # cyan
    "#f032e6",  # magenta
    "#bfef45",  # lime
    "#a35cff",  # violet
    "#ffa3c9",  # pink
    "#1fb5a3",  # teal
    "#ffffff",  # white
    "#d2b48c",  # tan
    "#8fa8ff",  # periwinkle
)

# The friend (star, ring, arrow, curve, uncertainty ellipse) and a landmark to re-check.
FRIEND_COLOUR_HEX = "#ffd400"
SUSPECT_COLOUR_HEX = "#ff1f1f"
# Outline under every stroke and letter, so colours read on bright photos too.
OUTLINE_COLOUR_HEX = "#141414"


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
