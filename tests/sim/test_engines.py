"""The science over every engine, in one parametrised suite (after Nengo's ``Simulator`` fixture).

Each test takes the ``simulator`` fixture: ``simulator(configs) -> episodes`` on the engine under test (the CPU loop,
``mujoco.batch`` lock-step worlds, MuJoCo Warp on Warp's CPU device). The same physics claims hold on each: AMOSII
walks forward and turns on the spot both ways (Table 1's steering), the plastic network escapes a dead end, a run
repeats bit for bit, and the engine agrees with the CPU loop (bit for bit for ``mujoco.batch``; within Warp's float32
tolerance for Warp).
"""

import os
from dataclasses import replace

import numpy as np
import pytest

from neurowalk.metrics import exit_step, forward_displacement, heading_change
from neurowalk.sim.config import engine_names
from neurowalk.sim.engine_interface import Engine, EngineOptions
from neurowalk.sim.engines import ENGINES, call_groups
from neurowalk.sim.episode import EpisodeConfig, run_episode

WALK = EpisodeConfig(arena="open", controller="fixed", steer=(-1.0, -1.0), steps=150, noise=0.0)
LEFT = replace(WALK, steer=(-1.0, 1.0))
RIGHT = replace(WALK, steer=(1.0, -1.0))
STARTED = 50  # control steps (5 s): the gait's start is over


class Simulator:
    """Runs configs on one engine: ``simulator(configs)`` -> one episode per config (one call for many worlds)."""

    def __init__(self, engine: Engine, options: EngineOptions, config_engine: str, tolerance: float) -> None:
        self.engine, self.options, self.config_engine, self.tolerance = engine, options, config_engine, tolerance

    def __call__(self, configs: list[EpisodeConfig]) -> list:
        """Configs of one group key share a call (many worlds); the episodes come back in the configs' order."""
        configs = [replace(c, engine=self.config_engine) for c in configs]
        out: list = [None] * len(configs)
        for idx, engine in call_groups(configs, self.options, engine_of=lambda c: self.engine):
            batch = [configs[i] for i in idx]
            engine.check(batch, self.options)
            for i, ep in zip(idx, engine.run(batch, self.options), strict=True):
                out[i] = ep
        return out

    @property
    def on_warp_cpu(self) -> bool:
        return self.engine is ENGINES["warp"] and self.options.device == "cpu"


def _warp() -> Simulator:
    pytest.importorskip("mujoco_warp")
    device = os.environ.get("NEUROWALK_TEST_DEVICE", "cpu")  # cuda on a GPU machine: the same tests hold
    options = ENGINES["warp"].resolve(EngineOptions(device=device))
    return Simulator(ENGINES["warp"], options, "warp", 1e-3)


@pytest.fixture(
    params=[
        pytest.param("cpu", id="cpu-loop"),
        pytest.param("batch", id="mujoco.batch"),
        pytest.param("warp", id="warp", marks=pytest.mark.warp),
    ]
)
def simulator(request) -> Simulator:
    if request.param == "cpu":
        return Simulator(ENGINES["mujoco"], EngineOptions(), "mujoco", 0.0)
    if request.param == "batch":
        return Simulator(ENGINES["mujoco.batch"], EngineOptions(threads=2), "mujoco", 0.0)
    return _warp()


def _turned(ep, since: int = STARTED) -> float:
    """Heading change (rad, counter-clockwise positive) of a run from control step ``since`` to its end."""
    pose = ep.trajectory.pose[since:]
    return heading_change(pose, pose[0, 2])


def test_walks_forward_and_turns_on_the_spot_both_ways(simulator):
    walk, left, right = simulator([WALK, LEFT, RIGHT])
    start = walk.arena.start
    assert forward_displacement(walk.trajectory.pose, start) > 0.04  # m in 15 s: Table 1's forward walk
    # after the start (its first steps yaw the robot a little, the same way whatever the steering: the same model at
    # a quarter of the step does so too, docs/performance.md), rad in 10 s
    turned_left, turned_right = _turned(left), _turned(right)
    assert turned_left > 0.2 and turned_right < -0.2
    assert abs(turned_left + turned_right) < 0.35 * turned_left  # both ways at similar rates
    # walking turns far less than turning on the spot (the gait's sway)
    assert abs(_turned(walk)) < 0.5 * min(turned_left, -turned_right)
    for ep in (walk, left, right):
        assert ep.summary["completed"] and float(np.min(ep.trajectory.up_z)) > 0.9  # upright throughout


def test_a_run_repeats_bit_for_bit_and_seeds_differ(simulator):
    cfg = EpisodeConfig(arena="box", steps=60, seed=4)
    first, other = simulator([cfg, replace(cfg, seed=5)])
    again = simulator([cfg])[0]
    np.testing.assert_array_equal(first.trajectory.qpos, again.trajectory.qpos)
    np.testing.assert_array_equal(first.trajectory.b, again.trajectory.b)
    assert not np.array_equal(first.trajectory.us_distance, other.trajectory.us_distance)  # noise from the seed


def test_agrees_with_the_cpu_loop(simulator):
    """mujoco.batch: bit for bit; Warp (float32): poses within 1 mm over 15 s of walking and turning, and in the box
    poses and sonar readings of its wall within 1 mm over 4 s (too short to reach it: contacts with walls diverge in
    float32 after a while, as any two such runs)."""
    cfgs = [WALK, LEFT, EpisodeConfig(arena="box", steps=40, seed=1)]
    for cfg, ep in zip(cfgs, simulator(cfgs), strict=True):
        ref = run_episode(cfg)
        if simulator.tolerance == 0.0:
            np.testing.assert_array_equal(ep.trajectory.qpos, ref.trajectory.qpos)
            assert ep.summary["final_weights"] == ref.summary["final_weights"]
        else:
            np.testing.assert_allclose(ep.trajectory.pose, ref.trajectory.pose, atol=simulator.tolerance)
            np.testing.assert_allclose(ep.trajectory.us_distance, ref.trajectory.us_distance, atol=simulator.tolerance)
    assert np.isfinite(ref.trajectory.us_distance).any()  # the box's wall in the sonars' range


@pytest.mark.slow
def test_the_plastic_network_escapes_a_dead_end(simulator):
    """The paper's dead-end run (5000 steps): the plastic network leaves the simple deadlock, seeds 0 and 1."""
    if simulator.on_warp_cpu:
        pytest.skip(
            "two 5000-step runs take minutes on Warp's CPU device; on a GPU: `neurowalk figure fig5 --engine warp`"
        )
    cfgs = [EpisodeConfig(arena="simple-deadlock", steps=5000, seed=s) for s in (0, 1)]
    for ep in simulator(cfgs):
        step = exit_step(ep.trajectory.pose, ep.arena)
        assert ep.summary["escaped"] and step is not None and step < 5000


def test_the_runner_groups_by_engine_and_keeps_the_order():
    """Mixed bodies and lengths through the one runner: each run is its config's, in the configs' order, as
    run_episode gives it."""
    from neurowalk.experiments.study_runs import Term, run_all

    pose = Term("pose", lambda ep: {"pose": ep.trajectory.pose}, arrays={"pose": "float64"})

    cfgs = [
        EpisodeConfig(arena="box", steps=30, seed=1),
        EpisodeConfig(arena="box", body="surrogate", steps=40, seed=1),
        EpisodeConfig(arena="box", steps=20, seed=2),
    ]
    for cfg, run in zip(cfgs, run_all(cfgs, (pose,), workers=1, progress=False), strict=True):
        assert run.config == cfg
        np.testing.assert_array_equal(run.kept["pose"]["pose"], run_episode(cfg).trajectory.pose)


def test_one_table_names_every_engine_a_config_may_name():
    """The engines a config may name (what the bodies run on) are the table's, and each engine's name is its key."""
    assert set(engine_names()) == set(ENGINES) and list(ENGINES) == ["mujoco", "mujoco.batch", "warp"]
    assert all(engine.name == name for name, engine in ENGINES.items())
