"""The intervals the solver benchmark prints beside its medians and 90th percentiles
(benchmarks/solverbench/common.py): two of the values that hold the population's quantile
between them at least 95 % of the time, and no wider than that needs."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parents[2] / "benchmarks"))

from solverbench.common import quantile_interval


@pytest.mark.parametrize(("q", "truth"), [(0.5, math.log(2.0)), (0.9, math.log(10.0))])
def test_the_interval_holds_the_quantile_about_95_percent_of_the_time(
    q: float, truth: float
) -> None:
    """Samples of 500 errors (exponential: skewed, as pixel errors are), 400 times."""
    rng = np.random.default_rng(20261129)
    held = []
    for _ in range(400):
        low, high = quantile_interval(rng.exponential(1.0, 500), q)
        held.append(low <= truth <= high)
    assert 0.93 <= np.mean(held) <= 0.995


def test_the_ends_are_order_statistics_near_the_binomial_quantiles() -> None:
    """For the median of 500 values the ranks are 228 and 273 (of 1 to 500): the binomial
    (500, 0.5) count below the median lies in 228-272 with probability 95.6 %."""
    values = np.arange(1.0, 501.0)
    assert quantile_interval(values[::-1], 0.5) == (228.0, 273.0)


def test_too_few_values_leave_an_end_open_and_none_say_nothing() -> None:
    assert quantile_interval([1.0, 2.0, 3.0], 0.9) == (1.0, math.inf)
    low, high = quantile_interval([], 0.5)
    assert math.isnan(low)
    assert math.isnan(high)


def test_infinite_errors_count_as_the_largest() -> None:
    """A refusal is an infinite error: the upper end becomes infinite once enough are."""
    values = [1.0] * 250 + [math.inf] * 250
    assert quantile_interval(values, 0.5) == (1.0, math.inf)
