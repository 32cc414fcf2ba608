"""How far a point is from a drawn curve: the tests and the benchmark grade the level
(``curve2``, pieces of polylines in px) by it."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from shared_solver.projective import Array


def distance_to(pieces: Sequence[Sequence[Sequence[float]]], point: Array) -> float:
    """The distance (px) from ``point`` (2,) to the nearest segment of the polylines
    ``pieces`` (each [[x, y], ...]); inf when there is no segment."""
    best = math.inf
    for piece in pieces:
        line = np.asarray(piece, dtype=np.float64)
        if len(line) < 2:
            continue
        start, along = line[:-1], np.diff(line, axis=0)
        lengths = np.einsum("ni,ni->n", along, along)
        t = np.clip(np.einsum("ni,ni->n", point - start, along) / np.maximum(lengths, 1e-300), 0, 1)
        nearest = start + t[:, None] * along
        best = min(best, float(np.hypot(*(nearest - point).T).min()))
    return best
