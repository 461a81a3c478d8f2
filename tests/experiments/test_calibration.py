"""Calibration of the surrogate: the measurements recover known motions, and the command writes a usable file."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from neurowalk.body.surrogate import load_calibration
from neurowalk.cli import main
from neurowalk.experiments.calibration import body_velocity, fit_lag, predict, sway_fit


def test_body_velocity_of_a_circle() -> None:
    t = np.arange(1001) / 10.0  # s
    w, r = 0.05, 0.3  # rad/s, m: a left turn at 1.5 cm/s
    pose = np.column_stack([r * np.sin(w * t), r * (1 - np.cos(w * t)), w * t])
    v = body_velocity(pose, 10.0)
    assert v[0] == pytest.approx(w * r, rel=1e-3) and abs(v[1]) < 1e-5 and v[2] == pytest.approx(w, rel=1e-9)


def test_lag_fit_recovers_a_known_delay_and_time_constant() -> None:
    hz, delay, tau = 10.0, 16, 3.0
    alpha = 1.0 - math.exp(-1.0 / (hz * tau))
    runs = []
    for before, after in (((0.012, 0, 0), (0.001, 0, 0.045)), ((0.001, 0, 0.045), (0.001, 0, -0.045))):
        v0, cmd = np.array(before), np.tile(after, (300, 1))
        runs.append((np.zeros(3), v0, cmd, predict(np.zeros(3), v0, cmd, delay, alpha, 1 / hz)))
    d, t, err = fit_lag(runs, hz)
    assert (d, t) == (delay, tau) and err < 1e-9


def test_sway_fit_finds_period_and_phase() -> None:
    k = 300 + np.arange(600)
    r = 0.05 * np.sin(2 * np.pi * k / 87.5 + 1.0)
    period, phase = sway_fit(r, 300)
    assert period == pytest.approx(87.5, abs=0.06) and phase == pytest.approx(1.0, abs=0.05)


def test_calibrate_writes_a_file_the_surrogate_reads(tmp_path: Path) -> None:
    out = tmp_path / "cal.json"
    assert main(["calibrate", "--quick", "--out", str(out)]) == 0
    cal = load_calibration(out)
    i = int(np.argmin(np.abs(cal.grid + 1.0)))
    assert cal.velocity[i, i, 0] > 0.005  # forward at (-1, -1), m/s
    assert cal.meta["validation"]["speed_error_max"] < 0.15
    assert out.with_suffix(".png").is_file()
