"""benchmarks/side_by_side.py's paired rounds: each side's interpreter times what it is asked, and the interval of the
median ratio is the distribution-free one it says."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from side_by_side import HERE as ROOT
from side_by_side import MEASURES, Side, median_interval


def test_the_interval_takes_the_order_statistics_of_the_binomial() -> None:
    """20 rounds: P(Binomial(20, 1/2) <= 5) = 0.021 <= 0.025 < P(<= 6) = 0.058, so the 6th and the 15th of the sorted
    ratios; too few rounds for 95%: the whole range."""
    values = [float(v) for v in range(20, 0, -1)]
    assert median_interval(values) == (6.0, 15.0)
    assert math.comb(20, 0) + sum(math.comb(20, k) for k in range(1, 6)) <= 0.025 * 2**20
    assert median_interval([3.0, 1.0, 2.0]) == (1.0, 3.0)


def test_the_interval_holds_the_median_of_its_population_at_least_95_times_in_100() -> None:
    rng = np.random.default_rng(0)
    held = 0
    for _ in range(2000):
        low, high = median_interval(list(rng.lognormal(0.0, 0.1, 30)))  # population median: exp(0) = 1
        held += low <= 1.0 <= high
    assert held / 2000 >= 0.95


def test_a_side_times_one_repetition_per_request_and_its_measures_are_python(tmp_path: Path) -> None:
    side = Side(ROOT, "import time\ncalls = []", "calls.append(1)\ntime.sleep(0.01)\nsteps = 10 * len(calls)", tmp_path)
    first, second = side.rate(), side.rate()
    side.close()
    assert 0 < first <= 20 / 0.01 and 0 < second <= 30 / 0.01  # after the untimed one: 2, then 3 calls of >= 10 ms
    for setup, body in MEASURES.values():
        compile(setup.format_map(_Sizes()), "setup", "exec")
        compile(body.format_map(_Sizes()), "body", "exec")


class _Sizes(dict):
    def __missing__(self, key: str) -> str:
        return "3"
