"""Run lengths in seconds of simulated time, and the real-robot comparison entry of Fig. 8-10."""

import pytest

from neurowalk.experiments.suites.timing import (
    REAL_ROBOT_HZ,
    quick_note,
    quick_seconds,
    real_robot_entry,
    steps_for,
    time_stats,
)


def test_seconds_become_control_steps_at_the_rate():
    assert steps_for(500.0, 10.0) == 5000  # today's 10 Hz runs, unchanged
    assert steps_for(500.0, 27.0) == 13_500
    assert steps_for(1.0, 27.0) == 27 and steps_for(0.4, 27.0) == 11
    assert steps_for(0.01, 10.0) == 1  # never zero steps


def test_quick_runs_keep_their_seconds_unless_the_step_cap_binds():
    assert quick_seconds(1200.0, 12_000, 10.0) == 1200.0
    assert quick_seconds(1200.0, 12_000, 27.0) == pytest.approx(12_000 / 27)
    assert quick_note(1200.0, 1200.0, 10.0) is None
    assert "27 Hz" in quick_note(1200.0, 12_000 / 27, 27.0)


def test_time_stats_over_the_runs_where_the_event_happened():
    s = time_stats([10.0, None, 30.0, 20.0])
    assert s["runs"] == 4 and s["happened"] == 3
    assert (s["median_s"], s["min_s"], s["max_s"]) == (20.0, 10.0, 30.0)
    assert time_stats([None])["median_s"] is None


def test_the_entry_says_whether_the_clocks_match():
    events = {"escaped": (50.0, "escaped (0:50 min)", [120.0, None])}
    at10 = real_robot_entry(events, 10.0, 500.0, "two seeds")
    at27 = real_robot_entry(events, REAL_ROBOT_HZ, 500.0, "two seeds")
    assert at10["paper_control_hz"] == 27.0 and at10["control_hz"] == 10.0 and not at10["same_clock"]
    assert "not the fair comparison" in at10["note"] and "--control-hz 27" in at10["note"]
    assert at27["same_clock"] and "same 27 Hz" in at27["note"] and at27["run_s"] == 500.0
    e = at27["events"]["escaped"]
    assert e["paper_s"] == 50.0 and e["sim"]["median_s"] == 120.0 and e["sim"]["happened"] == 1
