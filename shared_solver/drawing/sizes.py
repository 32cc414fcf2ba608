"""How large the answer's shapes are on one photo, px: all grow with its diagonal, so they
read on a phone that shows the whole photo across its screen (one screen px is about
diagonal / 700 photo px)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..projective import Array

# A bracket's arm, as a fraction of the frame's shorter half-side.
BRACKET_ARM = 0.4
# The region's outline is drawn when its short semi-axis is at least this many frame
# half-sizes: narrower, its outline would run over the friend standing in it, whom the
# brackets frame anyway ...
OUTLINED_REGION = 0.6
# ... or when its long semi-axis is at least this many: then the brackets, around most of the
# photo, say little, and the outline shows along which line to look.
LONG_REGION = 5.0
# An arrow's head: its length as a fraction of the arrow's, and as wide as it is long.
ARROW_HEAD = 0.3
# A suspect's red ring: its radius in landmark rings.
SUSPECT_RING = 1.8


@dataclass(frozen=True)
class Sizes:
    """Sizes in px for one photo of ``width`` x ``height`` px."""

    width: int
    height: int
    room: float
    marker_radius: float
    landmark_radius: float
    frame_half: float
    margin: float
    arrow_length: float
    label_height: float

    @classmethod
    def of(cls, width: int, height: int) -> Sizes:
        diagonal = math.hypot(width, height)
        return cls(
            width=width,
            height=height,
            # Room left between a region and its brackets: about a stroke's width.
            room=max(2, round(diagonal / 900)),
            marker_radius=diagonal / 45,
            landmark_radius=max(5.0, diagonal / 160),
            # The frame around the friend is never smaller than a person 80 m away on a
            # phone's main camera (about 1.5 % of the diagonal), with room around them.
            frame_half=diagonal / 55,
            margin=diagonal / 30,
            arrow_length=diagonal / 7,
            # A label's height, to tell whether it fits above the frame.
            label_height=diagonal / 35,
        )

    @property
    def diagonal(self) -> float:
        return math.hypot(self.width, self.height)

    @property
    def centre(self) -> Array:
        return np.array([self.width / 2, self.height / 2])

    def contains(self, point: Array, pad: float = 0.0) -> bool:
        """Whether ``point`` is on the photo (edges at 0 and width/height), or within ``pad``."""
        x, y = point
        return bool(-pad <= x <= self.width + pad and -pad <= y <= self.height + pad)
