"""The suggestion benchmark's count of what lies behind its spots offered beyond 3 % of the
diagonal (benchmarks/suggestbench/arena_tables.py): one look-alike, asked for at every tap
noise and count of landmarks found, is one landmark, not one per offer."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parents[2] / "benchmarks"))

from suggestbench.arena_tables import far_sources
from suggestbench.arenas import Asked
from suggestbench.trials import Timed

from shared_solver.matching.search import Match
from shared_solver.matching.suggestion import Evidence

DIAGONAL = 3200.0


def asked(
    scene: int, direction: int, sigma: float, truth: tuple[float, float], off: float
) -> Asked:
    """A landmark whose search found a spot ``off`` (fraction of the diagonal) to the right
    of the truth."""
    point = np.array(truth) + np.array([off * DIAGONAL, 0.0])
    evidence = Evidence(Match(point, 0.9, 0.5, 1.0, 0.0), sigmas=0.5)
    return Asked(
        scene,
        sigma,
        3,
        direction,
        "banner",
        DIAGONAL,
        np.array(truth),
        10.0,
        Timed(evidence, 0.1, 0.1),
    )


def test_one_look_alike_offered_at_every_noise_is_one_landmark() -> None:
    items = [
        *(asked(18, 2, sigma, (1030.0, 706.0), 0.105) for sigma in (1.0, 3.0, 8.0)),
        asked(18, 1, 3.0, (838.0, 621.0), 0.2),  # the same arena, the other way
        asked(5, 1, 3.0, (2301.0, 450.0), 0.177),
        asked(6, 1, 3.0, (100.0, 100.0), 0.005),  # right: not counted
    ]
    assert far_sources(items, rule=lambda _: True) == (3, 2)
    assert far_sources(items, rule=lambda _: False) == (0, 0)
