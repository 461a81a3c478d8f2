"""Calibration of the surrogate: the measurements recover known motions, and the command writes a usable file."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from neurowalk.body.surrogate import load_calibration
from neurowalk.body.wheeled import WheeledParams
from neurowalk.cli import main
from neurowalk.experiments.calibration.calibrate import calibrate
from neurowalk.experiments.calibration.fit import body_velocity, fit_lag, outline, predict, sway_fit
from neurowalk.experiments.calibration.physics import geometry


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


def test_calibrating_the_wheeled_robot_on_a_tiny_grid() -> None:
    """The whole machinery on the wheeled body, steered directly: 3 x 3 pairs, 2 x 2 held out (a few seconds)."""
    cal = calibrate(grid=(-1.0, 0.0, 1.0), held_out=(-0.5, 0.5), workers=1, progress=False, body="wheeled")
    p = WheeledParams()
    v = cal.velocity  # [O1, O2]: index 0 = -1, 1 = 0, 2 = +1
    assert v[0, 0, 0] == pytest.approx(p.speed, rel=0.01) and v[2, 2, 0] == pytest.approx(-p.speed, rel=0.01)
    assert np.allclose(v[1, 1], 0.0, atol=1e-6)  # (0, 0) stops
    spin = 2 * p.speed / p.track  # rad/s: turning on the spot at full wheel speed, left at (-1, 1)
    assert v[0, 2, 2] == pytest.approx(spin, rel=0.05) and v[2, 0, 2] == pytest.approx(-spin, rel=0.05)
    assert np.abs(v[..., 1]).max() < 1e-4  # m/s: wheels do not slide sideways
    assert np.all(cal.sway == 0.0) and cal.meta["sway_measured_max_rad"] < 0.01  # no gait: no sway fitted
    assert cal.delay_steps <= 2 and cal.tau_s <= 0.5 and cal.startup_steps <= 3  # wheels respond within a step
    m = cal.meta
    assert m["command"] == "neurowalk calibrate --body wheeled" and m["surrogate"] == "surrogate-wheeled"
    assert m["validation"]["speed_error_max"] < 0.02 and m["validation"]["yaw_rate_error_max"] < 0.02
    assert len(m["validation"]["pairs"]) == 4


def test_the_wheeled_geometry_is_the_chassis_wheels_and_sensor_sites() -> None:
    circles, rays, us_range = geometry("wheeled")
    p = WheeledParams()
    assert (circles[:, 0] + circles[:, 2]).max() == pytest.approx(p.front, abs=1e-6)  # m: front face
    assert (circles[:, 0] - circles[:, 2]).min() == pytest.approx(p.front - p.length, abs=1e-6)  # rear face
    assert (circles[:, 1] + circles[:, 2]).max() == pytest.approx(p.width / 2, abs=1e-6)  # the wheels' outer faces
    assert circles[:, 2].max() <= 0.04 + 1e-12  # m: the chassis outline in small circles, not one wide chain
    x_us = p.front - p.us_inset
    assert rays[:, 0] == pytest.approx([x_us, x_us]) and rays[:, 1] == pytest.approx([p.us_y, -p.us_y])
    assert np.degrees(np.arctan2(rays[:, 3], rays[:, 2])) == pytest.approx([35.0, -35.0])  # left ray first
    assert us_range == p.us_range


def test_outline_circles_reach_the_rectangle_sides_and_leave_no_gap() -> None:
    a, b, r = 0.23, 0.17, 0.04
    c = outline(a, b, r)
    assert (np.abs(c[:, 0]) + r).max() == pytest.approx(a) and (np.abs(c[:, 1]) + r).max() == pytest.approx(b)
    side = np.sort(c[np.isclose(c[:, 1], b - r), 0])
    assert np.diff(side).max() <= r + 1e-12  # neighbours at most r apart along a side
    with pytest.raises(ValueError, match=r"0\.5"):
        outline(a, b, 0.5)


@pytest.mark.parametrize("body", ["tank", "surrogate"])
def test_calibrate_bad_body_exits_2(body: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["calibrate", "--body", body, "--out", str(tmp_path / "c.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{body!r}" in err and "amosii, wheeled" in err
    assert not (tmp_path / "c.json").exists()


def test_a_grid_without_the_forward_pair_is_refused() -> None:
    with pytest.raises(ValueError, match=r"\[0\.0, 1\.0\]"):
        calibrate(grid=(0.0, 1.0), body="wheeled", progress=False)
