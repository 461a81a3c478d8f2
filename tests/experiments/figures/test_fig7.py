import json

import pytest

from neurowalk.cli import main
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.study import compute


def test_fig7_from_physics_is_a_wave_gait(tmp_path):
    assert main(["figure", "fig7", "--out", str(tmp_path), "--quick"]) == 0
    s = json.loads((tmp_path / "fig7.json").read_text())
    c = s["conditions"]
    for name, cond in c.items():
        assert cond["leg_order"] == ["R3", "R2", "R1", "L3", "L2", "L1"], name
        assert 0.08 <= cond["swing_fraction"] <= 0.2, name  # about 1/6 of the cycle is swing
        assert cond["time_two_or_more_in_swing"] < 0.15, name  # mostly one leg at a time
        assert 8.0 < cond["period_s"] < 9.5, name  # CPG period 87.5 steps = 8.75 s
    assert set(c["forward"]["stroke_direction"].values()) == {1.0}
    assert set(c["backward"]["stroke_direction"].values()) == {-1.0}
    assert c["forward"]["speed_m_per_s"] > 0 > c["backward"]["speed_m_per_s"]
    assert c["turn left"]["turning_rate_deg_per_s"] > 0 > c["turn right"]["turning_rate_deg_per_s"]
    assert (tmp_path / "fig7.png").stat().st_size > 50_000
    w = s["window"]  # one window for every number: after the warm-up, the rest of the run
    assert (w["from_step"], w["to_step"], w["duration_s"]) == (300, 599, pytest.approx(29.9))
    assert s["control_hz"] == 10.0


def test_fig7_at_27_hz_measures_on_the_27_hz_clock():
    s = compute(FIGURES["fig7"], Settings(quick=True, control_hz=27.0)).summary
    assert s["control_hz"] == 27.0 and s["window"]["duration_s"] == pytest.approx(299 / 27.0)
    c = s["conditions"]
    for name, cond in c.items():
        assert 87.5 / 27 * 0.9 < cond["period_s"] < 87.5 / 27 * 1.1, name  # the same 87.5-step cycle, in 27 Hz s
    assert c["forward"]["speed_m_per_s"] > 0.025  # about 2.7 x the 1.4 cm/s at 10 Hz
    assert c["turn left"]["turning_rate_deg_per_s"] > 5.0  # about 2.7 x the 2.6 deg/s at 10 Hz
