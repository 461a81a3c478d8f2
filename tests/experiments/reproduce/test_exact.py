"""Boschloo's exact test of two counts and its power (``experiments/reproduce/exact.py``), against scipy's."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import boschloo_exact

from neurowalk.experiments.reproduce import exact
from neurowalk.experiments.reproduce.claims import rate


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 30), st.integers(1, 30), st.data())
def test_the_p_value_is_scipys(n1: int, n2: int, data: st.DataObject) -> None:
    k1, k2 = data.draw(st.integers(0, n1)), data.draw(st.integers(0, n2))
    got = exact.boschloo(k1, n1, k2, n2)
    want = boschloo_exact([[k1, k2], [n1 - k1, n2 - k2]], alternative="two-sided", n=64).pvalue
    assert got.p_value == pytest.approx(want, abs=2e-6)
    assert 0.0 <= got.p_value <= 1.0
    assert exact.boschloo(k2, n2, k1, n1).p_value == pytest.approx(got.p_value, abs=1e-9)  # the samples swap


# The five counts of issue 59, neurowalk's against the paper's 49/50, with the verdicts its rule states.
FIVE = [
    ("table2-1000, authors' network, by coverage", 961, 1000, "reproduced"),
    ("table2-1000, authors' network, not stuck", 953, 1000, "reproduced"),
    ("table2-1000, paper's reading, by coverage", 905, 1000, "reproduced"),
    ("table2-physics, paper's reading, not stuck", 43, 50, "not"),
    ("table2-1000, paper's reading, not stuck", 872, 1000, "not"),
]


@pytest.mark.parametrize(("what", "k", "n", "verdict"), FIVE)
def test_the_five_counts(what: str, k: int, n: int, verdict: str) -> None:
    c = rate(what, 49, 50, k, n)
    want = boschloo_exact([[k, 49], [n - k, 1]], alternative="two-sided", n=64).pvalue
    assert c.test is not None and c.test["p_value"] == pytest.approx(want, abs=2e-6)
    assert c.verdict == verdict
    assert "Boschloo" in c.rule and "both" in c.rule and "80% power" in c.rule  # the rule says its test
    assert c.to_json()["test"]["detectable"]["below"] > 0.05  # 50 environments cannot see a 5-point shortfall


def test_significant_counts_are_partly_within_ten_points() -> None:
    assert rate("t", 49, 50, 8900, 10000).verdict == "partly"  # 89% against 98%: significant, 9 points
    assert rate("t", 49, 50, 8700, 10000).verdict == "not"  # 11 points
    assert rate("t", 49, 50, 0, 0).verdict == "not"


def test_the_size_and_power_of_the_test() -> None:
    # the size: at equal rates the test rejects no more often than alpha (it is exact), at any common rate
    for p in (0.1, 0.5, 0.9, 0.98):
        assert exact.power(p, 40, p, 30) <= 0.05 + 1e-12
    # the power grows with the difference and with the samples
    assert exact.power(0.7, 50, 0.98, 50) < exact.power(0.5, 50, 0.98, 50)
    assert exact.power(0.85, 50, 0.98, 50) < exact.power(0.85, 1000, 0.98, 50)


def test_the_papers_fifty_bound_what_can_be_detected() -> None:
    d50 = exact.detectable(0.98, 50, 50)["below"]
    d1000 = exact.detectable(0.98, 50, 1000)["below"]
    d4000 = exact.detectable(0.98, 50, 4000)["below"]
    assert d50 > d1000 > d4000 > 0.06  # more of neurowalk's runs help, down to the paper's own 50's limit
    assert exact.power(0.98 - d1000, 1000, 0.98, 50) == pytest.approx(0.8, abs=0.01)
    assert exact.detectable(0.98, 50, 1000)["above"] is None  # 98% leaves no room above to detect


def test_bad_counts() -> None:
    with pytest.raises(ValueError, match="0 <= k <= n"):
        exact.boschloo(3, 2, 1, 5)
    with pytest.raises(ValueError, match="n >= 1"):
        exact.boschloo(0, 0, 1, 5)
