"""The arrow at the photo's border towards a friend out of the photo."""

from __future__ import annotations

import math

import numpy as np

from .. import words
from ..projective import Array
from ..result import Homogeneous, Pixel
from .shapes import ArrowShape
from .sizes import ARROW_HEAD, Sizes

# Beyond this many photo diagonals a distance in px means nothing to a person: "far off".
_FAR_OFF_DIAGONALS = 100


def towards(
    pixel: Pixel | None, homogeneous: Homogeneous | None, sizes: Sizes
) -> ArrowShape | None:
    """The arrow to a friend at ``pixel`` outside the photo, or at infinity along the
    oriented ``homogeneous`` (``w == 0``); None when they are in the photo or nowhere."""
    if pixel is not None and all(map(math.isfinite, pixel)):
        at = np.array(pixel)
        if sizes.contains(at):
            return None
        x, y = pixel
        # The same "beyond the edge" distance as solve's warning, so the two numbers agree.
        beyond = max(-x, x - sizes.width, -y, y - sizes.height)
        far = beyond > _FAR_OFF_DIAGONALS * sizes.diagonal
        text = words.DRAWN_FAR_OFF if far else words.drawn_off_photo(beyond)
        return border_arrow(at - sizes.centre, text, sizes)
    if homogeneous is not None and all(map(math.isfinite, homogeneous)):
        # At infinity: solve orients epipoles, so (x, y) points to the friend's side.
        x, y, _ = homogeneous
        direction = np.array([x, y])
        if np.any(direction != 0):
            return border_arrow(direction, words.DRAWN_FAR_OFF, sizes)
    return None


def border_arrow(direction: Array, text: str, sizes: Sizes) -> ArrowShape:
    """An arrow ending at the border (inset by the margin), on the ray from the photo's
    centre along ``direction`` (2,)."""
    unit = direction / np.hypot(*direction)
    half = np.maximum([sizes.width / 2 - sizes.margin, sizes.height / 2 - sizes.margin], 1.0)
    with np.errstate(divide="ignore"):
        reach = float(np.min(half / np.abs(unit)))
    tip = sizes.centre + reach * unit
    tail = tip - min(sizes.arrow_length, 0.8 * reach) * unit
    length = float(np.hypot(*(tip - tail)))
    return ArrowShape(
        tail=(float(tail[0]), float(tail[1])),
        tip=(float(tip[0]), float(tip[1])),
        direction=(float(unit[0]), float(unit[1])),
        head=min(length, ARROW_HEAD * sizes.arrow_length),
        text=text,
    )
