"""The verdict rules of neurowalk reproduce: each verdict where the rule says, the Wilson interval's properties."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from neurowalk.experiments.reproduce.claims import Claim, holds, interval, outcome, overall, rate, value, wilson


@given(st.integers(0, 500), st.integers(1, 500))
def test_wilson_interval_holds_the_rate_and_narrows_with_n(k, n):
    k = min(k, n)
    lo, hi = wilson(k, n)
    assert 0.0 <= lo <= k / n <= hi <= 1.0
    lo4, hi4 = wilson(4 * k, 4 * n)  # the same rate on four times the runs
    assert hi4 - lo4 < hi - lo + 1e-12


def test_wilson_known_value_and_bad_counts():
    lo, hi = wilson(49, 50)  # the paper's 49/50: about 89.5%-99.6%
    assert lo == pytest.approx(0.8950, abs=1e-3) and hi == pytest.approx(0.9965, abs=1e-3)
    assert wilson(0, 0) == (0.0, 1.0)
    with pytest.raises(ValueError):
        wilson(3, 2)


def test_outcome_reproduced_only_where_the_papers_outcome_is_typical():
    assert outcome("escapes", "escaped", 10, 10).verdict == "reproduced"
    assert outcome("escapes", "escaped", 2, 3).verdict == "reproduced"
    assert outcome("escapes", "escaped", 0, 10).verdict == "not"
    assert outcome("escapes", "escaped", 6, 10).verdict == "partly"
    assert outcome("escapes", "escaped", 0, 0).verdict == "not"
    assert outcome("escapes", "escaped", 3, 3).interval[0] < 0.5  # the interval says how little three runs say


def test_rate_tests_both_counts():
    assert rate("t2", 49, 50, 48, 50).verdict == "reproduced"
    assert rate("t2", 49, 50, 44, 50).verdict == "reproduced"  # 88% against 98% on 50 each: p = 0.09, no evidence
    assert rate("t2", 49, 50, 25, 50).verdict == "not"
    c = rate("t2", 49, 50, 48, 50)
    assert c.measured == "48/50" and c.paper == "49/50" and c.interval[0] < 0.96 < c.interval[1]


def test_timing_factor_rule_and_missing_event():
    assert interval("escape", 40, 60).verdict == "reproduced"
    assert interval("escape", 40, 120).verdict == "partly"
    assert interval("escape", 40, 16).verdict == "partly"  # the factor counts both ways
    assert interval("escape", 40, 400).verdict == "not"
    assert interval("escape", 40, None).verdict == "not"
    assert interval("escape", 40, math.nan).measured is None
    # the paper's 6 s is known to +-1 s (two stamps to the second): 10.4 s is 1.49 x 7 s, 10.6 s is beyond
    assert interval("climb", 6, 10.4).verdict == "reproduced" and interval("climb", 6, 10.6).verdict == "partly"
    assert interval("climb", 6, 3.4).verdict == "reproduced"  # 5 s / 3.4 s = 1.47


def test_value_tolerances():
    assert value("b*", 4.63, 4.64, 0.05).verdict == "reproduced"
    assert value("b*", 4.63, 4.73, 0.05).verdict == "partly"
    assert value("b*", 4.63, 5.63, 0.05).verdict == "not"


def test_overall_and_bad_verdicts():
    yes = holds("a", "x", True, 1, "why")
    no = holds("b", "x", False, 0, "why")
    half = Claim("c", 1, 0.5, "partly", "rule")
    assert overall([yes, yes]) == ("reproduced", "all 2 reproduced")
    assert overall([no, no]) == ("not", "all 2 not reproduced: b; b")
    assert overall([yes, no]) == ("partly", "1 of 2 reproduced; not: b")
    # none reproduced but not all not: partly, as the report's rule says ("not where all are not")
    assert overall([half, no, half]) == ("partly", "0 of 3 reproduced; partly: c; c; not: b")
    assert overall([])[0] == "not"
    with pytest.raises(ValueError, match="verdict"):
        Claim("a", 1, 1, "maybe", "rule")
    assert yes.to_json()["interval"] is None


def test_a_claim_not_reproduced_gets_a_cause_and_an_unknown_one_is_unexplained(tmp_path):
    from neurowalk.experiments.reproduce.causes import with_causes

    yes, no = holds("a", "x", True, 1, "why"), holds("the one", "x", False, 0, "why")
    out = with_causes("nothing-known", [yes, no], {}, tmp_path)
    assert out[0].cause is None and out[1].cause == {"kind": "unexplained", "why": "no measurement names a cause yet"}
    # fig9-27hz's static network: the run length, from the runs' own exit times
    stuck = holds("static network gets stuck in the path (Fig. 9)", "stuck", False, "0/10", "why")
    summary = {"control_hz": 27.0, "duration_s": 800.0, "counts": {"static": {"runs": [{"out_time_s": 264.0},
               {"out_time_s": 339.0}]}}}  # fmt: skip
    (got,) = with_causes("fig9-27hz", [stuck], summary, tmp_path)
    assert got.cause["kind"] == "a neurowalk substitute" and "264-339 s" in got.cause["why"]
    assert "7,128-9,153 control steps" in got.cause["why"]
    # Table 2's shortfall without the ablation's record: unexplained, not invented
    t2 = rate("plastic-paper: not stuck", 49, 50, 40, 50)
    assert with_causes("table2", [t2], {}, tmp_path)[0].cause["kind"] == "unexplained"
