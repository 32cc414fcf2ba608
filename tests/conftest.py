"""Shared test fixtures: the real temple calibration and reproducible random sources."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).parent / "data"
TEMPLE = DATA / "temple"


@pytest.fixture
def temple_parameters() -> Path:
    """``templeSR_par.txt`` of the Middlebury templeSparseRing set (copied into tests/data)."""
    return TEMPLE / "templeSR_par.txt"


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261121)
