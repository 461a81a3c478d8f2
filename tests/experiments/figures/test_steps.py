"""The step-height sweep (figure ``steps``): run lengths and times at the figure's control rate."""

import pytest

from neurowalk.experiments import Settings
from neurowalk.experiments.figures import steps
from neurowalk.runners.specs import spec_key


@pytest.mark.parametrize(("quick", "hz", "n_steps"), [(True, 10.0, 3000), (True, 27.0, 3000), (False, 27.0, 8100)])
def test_runs_and_times_follow_the_control_rate(monkeypatch, tmp_path, quick, hz, n_steps):
    seen = []

    def run_store(specs, folder, workers):
        seen.extend(specs)
        return {spec_key(s): {"exit_step": 270 if s["arena_opts"]["height"] < 0.1 else None} for s in specs}, None

    monkeypatch.setattr(steps, "run_store", run_store)
    s = steps.run(Settings(quick=quick, seeds=1, out=tmp_path, control_hz=hz)).summary
    assert seen and all(x["control_hz"] == hz and x["steps"] == n_steps for x in seen)
    assert s["control_hz"] == hz and s["steps"] == n_steps and s["duration_s"] == pytest.approx(n_steps / hz)
    assert (s["quick_note"] is not None) == (quick and hz == 27.0)  # the quick run shortened to 111 s at 27 Hz
    times = s["variants"]["neither"]["median_time_to_climb_s"]
    assert times["0.04"] == pytest.approx(270 / hz) and list(times.values())[-1] is None
