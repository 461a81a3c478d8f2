"""Climbing in physics: what each module adds, the Fig. 10 track, and nothing lost on flat ground or in dead ends."""

import numpy as np
import pytest

from neurowalk.experiments.figures.fig10 import key_moments
from neurowalk.experiments.suites.climbing import climbed, step_spec, track_spec, track_success
from neurowalk.runners.specs import to_config
from neurowalk.sim.episode import EpisodeConfig, run_episode


def _climbs(height: float, variant: str, seed: int = 0) -> bool:
    return climbed(run_episode(to_config(step_spec(height, variant, seed))).summary)


@pytest.mark.slow
def test_a_10_cm_step_needs_both_backbone_control_and_reflexes():
    assert _climbs(0.10, "reflexes + backbone", 0) and _climbs(0.10, "reflexes + backbone", 1)
    assert not _climbs(0.10, "backbone only")
    assert not _climbs(0.10, "reflexes only")
    assert not _climbs(0.10, "neither")


@pytest.mark.slow
def test_backbone_control_alone_climbs_higher_than_the_reflexes_alone():
    assert _climbs(0.08, "backbone only") and not _climbs(0.08, "reflexes only")


@pytest.mark.slow
def test_without_climbing_modules_a_4_cm_step_stops_the_robot_with_them_it_is_climbed():
    assert not _climbs(0.04, "neither")
    assert _climbs(0.04, "reflexes + backbone")


@pytest.mark.slow
def test_climbing_track_climb_avoid_the_wall_climb_again():
    ep = run_episode(to_config(track_spec(0.06, 0)))
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
    assert abs(on["heading_change_deg"]) < 20


@pytest.mark.slow
def test_dead_end_results_hold_with_the_modules_on():
    from neurowalk.experiments.suites.deadends import VARIANTS, outcome_table

    variants = {"narrow-passage": VARIANTS["narrow-passage"]}
    narrow = outcome_table(4, variants=variants, progress=False, climbing=True)["counts"]["narrow-passage"]
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
