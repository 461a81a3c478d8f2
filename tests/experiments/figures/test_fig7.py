import json

from neurowalk.cli import main


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
