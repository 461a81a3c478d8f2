"""Climbing in physics: what each module adds, the Fig. 10 track, and nothing lost on flat ground or in dead ends."""

import numpy as np
import pytest

from fake_runs import dead_end_table, plan
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import fig10
from neurowalk.experiments.figures.fig10 import key_moments
from neurowalk.experiments.study import compute
from neurowalk.experiments.suites.climbing import (
    climb_step,
    climbed,
    first_platform_step,
    step_spec,
    track_spec,
    track_success,
)
from neurowalk.sim.episode import EpisodeConfig, run_episode


def _climbs(height: float, variant: str, seed: int = 0) -> bool:
    return climbed(run_episode(EpisodeConfig.from_spec(step_spec(height, variant, seed))).summary)


@pytest.mark.slow
def test_a_10_cm_step_needs_both_backbone_control_and_reflexes():
    assert _climbs(0.10, "reflexes + backbone", 0) and _climbs(0.10, "reflexes + backbone", 1)
    assert not _climbs(0.10, "backbone only")
    assert not _climbs(0.10, "reflexes only")
    assert not _climbs(0.10, "neither")


@pytest.mark.slow
@pytest.mark.parametrize("height", [0.07, 0.09])
def test_climb_with_the_plastic_network_climbs_the_heights_the_10_ms_step_lost_and_not_a_wall(height):
    def run(h: float, seed: int) -> dict:
        cfg = EpisodeConfig(arena="steps", arena_opts={"height": h}, controller="plastic", steps=3000, seed=seed,
                            reflexes=True, backbone=True, until="escaped")  # fmt: skip
        return run_episode(cfg).summary

    assert all(climbed(run(height, seed)) for seed in (0, 1))  # at the 10 ms step: 0 and 2 of 10 seeds
    if height == 0.09:
        assert not climbed(run(0.18, 0))  # a wall


@pytest.mark.slow
def test_backbone_control_alone_climbs_higher_than_the_reflexes_alone():
    assert _climbs(0.08, "backbone only") and not _climbs(0.08, "reflexes only")


@pytest.mark.slow
def test_without_climbing_modules_a_4_cm_step_stops_the_robot_with_them_it_is_climbed():
    """Climbed reliably by the steps figure's rule (at least 80% of the seeds): seed 0 does not at the 10 ms step (it
    does at 2.5 ms, and seeds 1-3 at both: the one climbing case of the figures not converged, issue 51's note)."""
    assert not _climbs(0.04, "neither")
    assert sum(_climbs(0.04, "reflexes + backbone", seed) for seed in range(5)) >= 4


@pytest.mark.slow
def test_climbing_track_climb_avoid_the_wall_climb_again():
    ep = run_episode(EpisodeConfig.from_spec(track_spec(0.06, 0)))
    assert track_success(ep.summary, 0.06)
    m = key_moments(ep.trajectory.targets[:, -1], ep.trajectory.outputs)
    assert m["first climb"] is not None and m["wall avoidance"] is not None and m["second climb"] is not None
    assert m["first climb"] < m["wall avoidance"] < m["second climb"] < ep.summary["exit_step"]
    z = ep.trajectory.qpos[:, 2]
    assert z[ep.summary["exit_step"]] > z[0] + 0.10  # two 6 cm steps up (it may walk back down later)


@pytest.mark.slow
def test_flat_walking_is_kept_with_the_modules_on():
    def walk(on: bool) -> dict:
        cfg = EpisodeConfig(arena="open", controller="fixed", steer=(-1.0, -1.0), steps=1500, reflexes=on, backbone=on)
        return run_episode(cfg).summary

    off, on = walk(False), walk(True)
    assert on["min_up_z"] > 0.95
    assert 0.7 < on["forward_displacement_m"] / off["forward_displacement_m"] < 1.3
    assert abs(on["heading_change_deg"]) < 25  # deg: the start's first steps yaw it more at the 10 ms step


@pytest.mark.slow
def test_dead_end_results_hold_with_the_modules_on():
    from neurowalk.experiments.suites.deadends import VARIANTS

    table = dead_end_table(Settings(seeds=4, climbing=True), {"narrow-passage": VARIANTS["narrow-passage"]})
    narrow = table["counts"]["narrow-passage"]
    assert narrow["plastic"]["escaped"] >= 3
    assert narrow["static"]["escaped"] <= 1


def test_key_moments_order_climbs_and_the_turn_between():
    bj = np.zeros(100)
    bj[10:15] = -0.5
    bj[60:65] = -0.5
    out = np.full((100, 2), -1.0)
    out[30:40, 1] = 1.0
    m = key_moments(bj, out)
    assert m == {"start": 0, "first climb": 10, "wall avoidance": 30, "second climb": 60}
    assert key_moments(np.zeros(100), out)["first climb"] is None


def test_track_runs_last_their_steps_and_step_runs_their_seconds_at_the_rate():
    assert track_spec(0.06, 0)["steps"] == 12_000 and track_spec(0.06, 0)["control_hz"] == 10.0  # as before
    assert track_spec(0.06, 0, control_hz=27.0)["steps"] == 12_000  # the networks' time: as many updates
    assert step_spec(0.04, "neither", 0)["steps"] == 3000
    assert step_spec(0.04, "neither", 0, control_hz=27.0) == {
        **step_spec(0.04, "neither", 0),
        "steps": 8100,
        "control_hz": 27.0,
    }


@pytest.mark.parametrize(("quick", "hz"), [(True, 10.0), (True, 27.0), (False, 27.0), (False, 10.0)])
def test_fig10_runs_as_many_control_steps_at_either_rate(quick, hz):
    seen = [p.config for p in plan("fig10", Settings(quick=quick, seeds=1, control_hz=hz))]
    assert seen and all(c.control_hz == hz and c.steps == 12_000 and c.until == "escaped" for c in seen)


def test_first_platform_is_the_trunk_centre_0_3_m_past_its_edge():
    x = np.linspace(0.0, 1.5, 16)  # 0.1 m a row; the first platform's edge is at x = 0.7 m
    pose = np.column_stack([x, np.zeros_like(x), np.zeros_like(x)])
    assert first_platform_step(pose, 0.06) == 10  # x = 1.0
    assert first_platform_step(pose[:10], 0.06) is None


def test_a_27_hz_track_run_reports_its_events_on_the_27_hz_clock(monkeypatch, tmp_path):
    monkeypatch.setattr(fig10, "TRACK_STEPS", 2700)  # 100 s: seed 0 is on the first platform by then
    res = compute(FIGURES["fig10"], Settings(seeds=1, out=tmp_path, control_hz=27.0))
    s = res.summary
    assert s["control_hz"] == 27.0 and s["duration_s"] == pytest.approx(2700 / 27.0)
    row = s["table"]["0.06"]["runs"][0]
    k = row["first_platform_step"]
    assert k is not None and k == first_platform_step(res.arrays["pose"], 0.06)  # the example drawn is this run
    assert row["first_platform_time_s"] == pytest.approx(k / 27.0)
    climb = s["real_robot"]["events"]["platform detected to on it"]
    assert climb["paper_s"] == 6.0  # 0:17 to 0:23
    bj = res.arrays["bj_command"]
    assert row["detected_time_s"] == pytest.approx(climb_step(bj, up=True) / 27.0)  # the example is this run
    assert 0 < row["detected_time_s"] < s["moments_s"]["first climb"] < row["first_platform_time_s"]  # up, then down
    assert climb["sim"]["times_s"] == [pytest.approx(row["first_platform_time_s"] - row["detected_time_s"])]
    assert s["real_robot"]["same_clock"] and s["real_robot"]["control_hz"] == 27.0
    assert res.arrays["t"][-1] == pytest.approx(2700 / 27.0, rel=1e-3)
    assert s["moments_s"]["first climb"] == pytest.approx(s["moments"]["first climb"] / 27.0)


@pytest.mark.parametrize(("hz", "heights"), [(10.0, 3), (27.0, 1)])
def test_fig10_runs_the_height_table_at_the_simulators_rate_only(hz, heights):
    runs = plan("fig10", Settings(seeds=2, control_hz=hz))
    assert len({p.config.arena_opts["step"] for p in runs}) == heights and len(runs) == 2 * heights
    examples = [p.config for p in runs if fig10.EXAMPLE in p.terms]
    assert [(c.arena_opts["step"], c.seed) for c in examples] == [(0.06, 0)]  # the example: a run of the table
