"""The arena judges: Fig. 5F's "escapes all deadlocks" asks for no held period over 300 s, and slow turns in place
(wedged, not held) are counted apart; a json written before the held periods is judged as before."""

from __future__ import annotations

from typing import Any

import numpy as np

from neurowalk import metrics
from neurowalk.experiments.figures.fig5 import claims as fig5
from neurowalk.experiments.suites.long_runs import wedged_counts

HZ = 10.0
STEPS = 100_000


def _run(yaw: np.ndarray) -> dict[str, Any]:
    """A long run's summary whose trunk stays within 5 cm of one spot with heading ``yaw`` (T,) rad."""
    rng = np.random.default_rng(0)
    pose = np.column_stack([1.0 + rng.uniform(-0.05, 0.05, (len(yaw), 2)), yaw])
    periods = metrics.wedged_periods(pose, control_hz=HZ)
    return {"trapped": False, "coverage": 0.2, "steps": STEPS, **metrics.wedged_summary(periods, HZ), "wedged": periods}


def _fig5_summary(plastic: dict[str, Any]) -> dict[str, Any]:
    """What :func:`fig5` reads: dead-end counts, the long runs, their wedged counts and the weights' range."""
    cell = {"escaped": 3, "trapped": 0, "runs": 3}
    runs = {"difficult (plastic)": plastic, "difficult (static)": {"coverage": 0.02, "trapped": True}}
    return {
        "table": {"counts": {a: {"plastic": cell} for a in ("simple-deadlock", "narrow-passage")}},
        "runs": runs,
        "wedged": wedged_counts({"difficult (plastic)": plastic}, control_hz=HZ),
        "time_step_reading": {"long_runs": "control steps"},
        "control_hz": HZ,
        "variant": "paper",
        "long_steps": STEPS,
        "fig5f": {
            "coverage": [0.2, 0.22],
            "median": 0.21,
            "sd": 0.014,
            "seconds": STEPS / HZ,
            "fits": [{"c_max": 0.3, "tau_s": 1000.0, "rms": 0.01}] * 2,
            "authors": {"coverage": 0.25, "fit": {"c_max": 0.4, "tau_s": 9000.0, "rms": 0.01}},
            "rule": "the rule",
        },
        "fig5g": {
            "first_step": 0,
            "last_step": STEPS - 1,
            "stride": 10,
            "finite": True,
            "max": {"b1": 1.0, "b2": 1.0},
            "min": {"b1": 0.5, "b2": 0.5, "c1": -1.0, "c2": -1.0},
        },
    }


def _held_claim(s: dict[str, Any]) -> dict[str, Any]:
    (claim,) = [c.to_json() for c in fig5(s, quick=False) if "held period" in c.what]
    return claim


def test_a_slow_turn_in_place_is_not_held_and_counts_as_turning():
    turn = np.radians(2.0 / HZ) * np.arange(4000)  # 400 s at 2 deg/s within the disc: wedged throughout
    claim = _held_claim(_fig5_summary(_run(turn)))
    assert claim["verdict"] == "reproduced"
    assert claim["measured"].startswith("0 held over 300 s; 1 wedged periods, of which 1 turning")


def test_a_robot_held_still_for_over_300_s_is_not_reproduced():
    still = 0.3 + np.radians(np.random.default_rng(1).uniform(-5.0, 5.0, 4000))  # 400 s, heading within 10 deg
    claim = _held_claim(_fig5_summary(_run(still)))
    assert claim["verdict"] == "not"
    assert claim["measured"].startswith("1 held over 300 s; 1 wedged periods, of which 0 turning")


def test_table2s_not_stuck_rule_says_the_300_s_it_applies_at_any_rate():
    from neurowalk.experiments.figures.table2 import claims as table2

    cell = {"controller": "plastic", "success": 45, "success_coverage": 44, "environments": 50}
    s = {"paper": {"success": 49, "environments": 50}, "body": "amosii", "steps": 54_000, "control_hz": 27.0,
         "counts": {"plastic-paper": cell}, "coverage_rule": "coverage"}  # fmt: skip
    rule = table2(s, False)[0].rule
    assert "last 300 s of simulated time" in rule and "3000 control steps not" not in rule
