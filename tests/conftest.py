"""Shared test fixtures: the real temple calibration and reproducible random sources; the
settings of every property-based test (Hypothesis); the longest tests first."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

# Every run draws the same examples (derandomize: a failure in CI is reproduced by running the
# test again) and writes no example database (.hypothesis); no deadline, as a shared 2-core
# machine makes timings noisy. Each test bounds its own examples (max_examples) to its share
# of the suite's time. HYPOTHESIS_PROFILE=explore draws new examples on every run, ten times as
# many (tests/absurd_inputs.py, examples()): to hunt for a failure by hand, never in CI.
settings.register_profile(
    "suite",
    derandomize=True,
    database=None,
    deadline=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
settings.register_profile("explore", settings.get_profile("suite"), derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "suite"))

DATA = Path(__file__).parent / "data"
TEMPLE = DATA / "temple"


@pytest.fixture
def temple_parameters() -> Path:
    """``templeSR_par.txt`` of the Middlebury templeSparseRing set (copied into tests/data)."""
    return TEMPLE / "templeSR_par.txt"


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261121)


# The files whose tests each take tens of seconds of the solver's: run first. Under
# ``--dist worksteal`` each worker starts with a contiguous half of the collection and steals
# from the other's tail, so a minute of real-camera answers left at the end (their file sorts
# late) ran on one worker while the other sat idle (make test-solver).
_LONGEST = ("test_real_cameras.py",)


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    items.sort(key=lambda item: item.path.name not in _LONGEST)
