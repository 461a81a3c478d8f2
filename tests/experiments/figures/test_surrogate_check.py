"""The surrogate study's calibration check: its held-out drives are planned runs of the one runner (not run by its
measure), the same drives the calibration measures."""

from __future__ import annotations

import numpy as np

from neurowalk.experiments import Settings
from neurowalk.experiments.calibration.fit import body_velocity
from neurowalk.experiments.calibration.physics import drive
from neurowalk.experiments.calibration.subjects import WARMUP, WINDOW
from neurowalk.experiments.figures import surrogate_check
from neurowalk.experiments.study_runs import run_all


def test_the_held_out_drives_are_plans_and_move_as_the_calibrations_drives():
    s = Settings(quick=True)
    plans = [p for p in surrogate_check.runs(s) if p.label[0] == "held-out"]
    pairs = surrogate_check.held_out(s)
    assert [p.label[1:] for p in plans] == pairs and len(pairs) == 16
    assert all(p.config.controller == "fixed" and p.config.steer == p.label[1:] for p in plans)
    assert all(p.config.noise == 0.0 and p.config.steps == WARMUP + WINDOW for p in plans)
    plan = plans[1]  # a turning pair (-0.4, -0.05)
    (run,) = run_all([plan.config], plan.terms, workers=1, progress=False)
    kept = run.kept["velocity"]["velocity"]
    calibrated = body_velocity(drive(np.tile(plan.config.steer, (WARMUP + WINDOW, 1)))[WARMUP:], 10.0)
    assert abs(kept[2]) > 0.005  # it turns
    # the calibration reads each pose one physics step before the control step's end; the run, after it
    np.testing.assert_allclose(kept, calibrated, rtol=0, atol=1e-5)
    assert not np.array_equal(kept, calibrated)
