"""AMOSII walks and steers in physics (issue 3 acceptance): 1000 control steps = 100 s at 10 Hz.

The walking tests run twice: as built in issue 3, and with the leg reflexes and backbone joint
control of Fig. 10 switched on (they must not change walking on flat ground).
"""

import numpy as np
import pytest

from neurowalk.body.physics import n_substeps
from neurowalk.sim.episode import EpisodeConfig, Streaming, run_episode

STEPS = 1000


@pytest.fixture(scope="module", params=[False, True], ids=["modules off", "reflexes and backbone on"])
def walks(request):
    steers = {"forward": (-1, -1), "backward": (1, 1), "left": (-1, 1), "right": (1, -1), "stop": (0, 0),
              "half": (-0.5, -0.5)}  # fmt: skip
    on = request.param
    return {k: run_episode(EpisodeConfig(controller="fixed", steer=s, steps=STEPS, reflexes=on, backbone=on))
            for k, s in steers.items()}  # fmt: skip


def test_forward_walks_straight_upright_without_warnings(walks):
    s = walks["forward"].summary
    assert s["forward_displacement_m"] >= 0.5
    assert abs(s["heading_change_deg"]) < 20  # deg: the start's first steps yaw it about 8 deg at the 10 ms step
    assert s["min_up_z"] >= 0.8
    assert s["simulation_warnings"] == {}


def test_backward(walks):
    assert walks["backward"].summary["forward_displacement_m"] <= -0.3
    assert walks["backward"].summary["min_up_z"] >= 0.8


def test_turns_on_the_spot_both_ways_at_similar_rates(walks):
    left, right = walks["left"].summary, walks["right"].summary
    assert left["heading_change_deg"] >= 45 and right["heading_change_deg"] <= -45
    assert left["net_displacement_m"] < 0.3 and right["net_displacement_m"] < 0.3
    ratio = left["heading_change_deg"] / -right["heading_change_deg"]
    assert 1 / 1.25 <= ratio <= 1.25


def test_stop_and_half_amplitude(walks):
    assert walks["stop"].summary["net_displacement_m"] < 0.05
    assert 0 < walks["half"].summary["forward_displacement_m"] < walks["forward"].summary["forward_displacement_m"]


def test_trajectory_contract(walks):
    tr = walks["forward"].trajectory
    assert len(tr) == STEPS
    for name, shape in {"t": (), "pose": (3,), "inputs": (2,), "outputs": (2,), "b": (2,), "q": (2,),
                        "targets": (19,), "joint_angles": (19,)}.items():  # fmt: skip
        assert getattr(tr, name).shape == (STEPS, *shape)
    assert np.allclose(np.diff(tr.t), 0.1)
    # Measured joint angles follow the commanded targets (servo tracking, same sign convention).
    err = np.abs(tr.joint_angles[300:, :18] - tr.targets[300:, :18])
    assert np.median(err) < np.deg2rad(5)


def test_same_seed_same_trajectory_bit_for_bit_and_seeds_differ():
    cfg = {"arena": "box", "arena_opts": {"distance": 0.6}, "controller": "plastic", "steps": 400}
    a = run_episode(EpisodeConfig(**cfg, seed=3)).trajectory
    b = run_episode(EpisodeConfig(**cfg, seed=3)).trajectory
    c = run_episode(EpisodeConfig(**cfg, seed=4)).trajectory
    np.testing.assert_array_equal(a.qpos, b.qpos)
    np.testing.assert_array_equal(a.outputs, b.outputs)
    assert not np.array_equal(a.qpos, c.qpos)  # sensor noise differs


def test_neural_controllers_turn_away_from_a_box_on_the_left():
    for mode in ("plastic", "static", "braitenberg"):
        ep = run_episode(EpisodeConfig(arena="box", arena_opts={"distance": 0.6, "offset": 0.35, "width": 0.5},
                                       controller=mode, steps=500))  # fmt: skip
        heading = np.degrees(np.unwrap(ep.trajectory.pose[:, 2]))
        on = np.flatnonzero(ep.trajectory.outputs[:, 0] > 0.9)
        assert len(on), mode  # O1 (left neuron) switched on
        assert heading[on[0] :].min() < heading[on[0]] - 10, mode  # obstacle on the left: from then on, turn right
        assert np.max(ep.trajectory.outputs[:, 1]) < 0, mode  # O2 stayed off


def test_bad_config_raises():
    with pytest.raises(ValueError, match="steps"):
        EpisodeConfig(steps=0)
    with pytest.raises(ValueError, match="controller"):
        EpisodeConfig(controller="wheeled")
    with pytest.raises(ValueError, match="steer"):
        EpisodeConfig(controller="fixed")
    assert n_substeps(10.0, 0.01) == 10  # the default step, the authors: 10 physics steps per control step
    assert n_substeps(10.0, 0.005) == 20
    assert n_substeps(27.0, 0.005) == 7  # 7.41 steps of 5 ms: 7 steps of 5.29 ms (set_control_rate)
    assert n_substeps(1000.0, 0.005) == 1


def test_long_runs_stream_chunks_and_keep_completed_steps_when_stopped(tmp_path):
    from neurowalk.sim.episode import RunInterruptedError
    from neurowalk.sim.trajectory import PartWriter

    cfg = EpisodeConfig(controller="plastic", arena="box", arena_opts={"distance": 0.6}, steps=250)
    whole = run_episode(cfg).trajectory
    parts = PartWriter(tmp_path / "parts")
    run_episode(cfg, stream=Streaming(sink=parts, chunk=100))
    streamed = parts.read()
    np.testing.assert_array_equal(streamed.qpos, whole.qpos)
    np.testing.assert_array_equal(streamed.pose, whole.pose)
    parts.remove()

    calls = []

    def stop_on_second(rows, start):
        calls.append((start, start + len(rows)))
        if len(calls) == 2:
            raise KeyboardInterrupt

    with pytest.raises(RunInterruptedError) as info:
        run_episode(cfg, stream=Streaming(sink=stop_on_second, chunk=100))
    ep = info.value.episode
    assert ep.summary["completed"] is False and ep.summary["steps"] == 200 == len(ep.trajectory)
    np.testing.assert_array_equal(ep.trajectory.qpos, whole.qpos[:200])


def test_summary_counts_wedged_periods_with_their_causes():
    # Pushing into a box for 130 s: wedged, the legs and trunk against it, the rays seeing it.
    push = run_episode(EpisodeConfig(arena="box", arena_opts={"distance": 0.3}, controller="fixed", steer=(-1, -1),
                                     steps=1300)).summary  # fmt: skip
    assert push["wedged_periods"] == 1 and push["wedged_causes"] == {"body contact": 1}
    (p,) = push["wedged"]
    assert push["longest_wedged_s"] == p["duration_s"] >= 100 and p["contact_fraction"] > 0.5
    assert p["blind_fraction"] < 0.5
    # Standing still in the open for 110 s: wedged with both rays blind, touching nothing.
    stand = run_episode(EpisodeConfig(controller="fixed", steer=(0, 0), steps=1100)).summary
    assert stand["wedged_causes"] == {"both rays blind": 1} and stand["wedged"][0]["contact_fraction"] == 0.0
    # Walking in the open: never wedged.
    walk = run_episode(EpisodeConfig(controller="fixed", steer=(-1, -1), steps=1100)).summary
    assert walk["wedged_periods"] == 0 and walk["longest_wedged_s"] == 0.0 and walk["wedged_causes"] == {}
    # The planar surrogate has the same keys; without legs there is no contact record.
    sur = run_episode(EpisodeConfig(controller="fixed", steer=(0, 0), steps=1100, body="surrogate")).summary
    assert sur["wedged_causes"] == {"both rays blind": 1} and sur["wedged"][0]["contact_fraction"] is None
