"""The step-height sweep (figure ``steps``): run lengths and times at the figure's control rate."""

import pytest

from fake_runs import fake_measure, summary_of
from neurowalk.experiments import Settings


@pytest.mark.parametrize(("quick", "hz", "n_steps"), [(True, 10.0, 3000), (True, 27.0, 3000), (False, 27.0, 8100)])
def test_runs_and_times_follow_the_control_rate(quick, hz, n_steps):
    def summary(c):
        return summary_of(c, exit_step=270 if c.arena_opts["height"] < 0.1 else None)

    seen, res = fake_measure("steps", Settings(quick=quick, seeds=1, control_hz=hz), summary)
    s = res.summary
    assert seen and all(x.control_hz == hz and x.steps == n_steps for x in seen)
    assert s["control_hz"] == hz and s["steps"] == n_steps and s["duration_s"] == pytest.approx(n_steps / hz)
    assert (s["quick_note"] is not None) == (quick and hz == 27.0)  # the quick run shortened to 111 s at 27 Hz
    times = s["variants"]["neither"]["median_time_to_climb_s"]
    assert times["0.04"] == pytest.approx(270 / hz) and list(times.values())[-1] is None
