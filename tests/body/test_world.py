"""The world protocol: every built-in body is a World (or a CompiledWorld) with the shapes the one loop reads."""

from __future__ import annotations

import numpy as np
import pytest

from neurowalk import EpisodeConfig, make_arena, make_body, run_episode
from neurowalk.body.noise import BLOCK, ColoredNoise, ColoredNoiseBatch
from neurowalk.body.world import CompiledWorld, OneWorld, World
from neurowalk.sim.batch import MujocoBatchWorlds
from neurowalk.sim.engine_interface import Streaming


@pytest.mark.parametrize("name", ["amosii", "wheeled"])
def test_a_per_step_body_is_one_world_with_the_loops_shapes(name):
    body = make_body(name, make_arena("box"))
    world = OneWorld(body)
    assert isinstance(world, World) and not isinstance(world, CompiledWorld) and world.n == 1
    world.reset([np.random.default_rng(0)])
    dist, foot = world.sense()
    assert dist.shape == (1, 2) and foot.shape == (1, 6)
    assert world.qpos.shape == (1, body.model.nq) and world.time.shape == (1,)
    t0, q0 = world.time.copy(), world.qpos.copy()
    world.apply(np.zeros((1, 19 if world.action == "targets" else 2)))
    world.advance()
    assert world.time[0] > t0[0] and not np.array_equal(world.qpos, q0)  # a control step of physics went by
    assert world.observation(0).us_distance.shape == (2,)


def test_many_amosii_worlds_are_a_world_of_n():
    configs = [EpisodeConfig(arena="box", steps=3, seed=s) for s in range(3)]
    worlds = MujocoBatchWorlds(configs)
    assert isinstance(worlds, World) and worlds.n == 3
    worlds.reset([np.random.default_rng(s) for s in range(3)])
    dist, foot = worlds.sense()
    assert dist.shape == (3, 2) and foot.shape == (3, 6) and worlds.qpos.shape == (3, worlds.nq)


def test_the_surrogate_is_a_compiled_world():
    body = make_body("surrogate", make_arena("box"))
    assert isinstance(body, CompiledWorld) and isinstance(body, World) and body.nq == 0  # chunks, or a step at a time
    assert {"pose", "us_distance", "b", "q"} <= set(body.columns) and "qpos" not in body.columns


def test_a_surrogate_run_is_the_same_whatever_its_chunks():
    """The loop hands the compiled world a chunk of steps a call: the chunk's size changes no number."""
    cfg = EpisodeConfig(arena="random", arena_opts={"n_boxes": 8}, body="surrogate", steps=2500, seed=3)
    whole = run_episode(cfg).trajectory
    rows = []
    parts = run_episode(cfg, stream=Streaming(chunk=333, sink=lambda r, start: rows.append((start, r.pose.copy()))))
    for name in ("pose", "inputs", "outputs", "b", "q", "us_distance", "t"):
        np.testing.assert_array_equal(getattr(parts.trajectory, name), getattr(whole, name), err_msg=name)
    assert [s for s, _ in rows] == list(range(0, 2500, 333))
    np.testing.assert_array_equal(np.concatenate([p for _, p in rows]), whole.pose)
    assert np.isnan(whole.targets).all() and (whole.up_z == 1.0).all() and whole.qpos.shape == (2500, 0)


def test_a_world_reset_on_its_own_draws_its_own_sources_noise():
    """A Gymnasium copy's new episode mid-run: each world's noise is, bit for bit, its own source's, across blocks."""
    sources = [ColoredNoise(4) for _ in range(3)]
    alone = [ColoredNoise(4) for _ in range(3)]
    batch = ColoredNoiseBatch(sources)
    batch.reset([np.random.default_rng(s) for s in range(3)])
    for s, src in enumerate(alone):
        src.reset(np.random.default_rng(s))
    for k in range(2 * BLOCK + 40):
        if k == 37:  # world 1 anew, out of step with the others' blocks from here on
            batch.reset([np.random.default_rng(99)], ids=[1])
            alone[1].reset(np.random.default_rng(99))
        v = batch.step()
        for i, src in enumerate(alone):
            np.testing.assert_array_equal(v[i], src.step(), err_msg=f"world {i}, step {k}")


class _Stepped:
    """A controller the loop cannot compile (it steps it by act()): the given one behind another type."""

    def __init__(self, inner):
        self.inner = inner

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def reset(self, rng=None):
        self.inner.reset(rng)

    def act(self, obs):
        return self.inner.act(obs)


@pytest.mark.parametrize("controller", ["plastic", "static"])
def test_a_controller_stepped_by_act_on_the_surrogate_is_its_compiled_run(controller):
    """The loop steps the surrogate one step at a time for a controller it cannot compile: the same run, bit for bit."""
    from neurowalk.sim.batch_control import BatchControllers
    from neurowalk.sim.config import build
    from neurowalk.sim.loop import run_worlds

    cfg = EpisodeConfig(arena="random", arena_opts={"n_boxes": 10}, body="surrogate", steps=1500, seed=5,
                        controller=controller)  # fmt: skip
    compiled = run_episode(cfg).trajectory
    arena, body, ctrl = build(cfg)
    stepped = run_worlds([cfg], [arena], body, BatchControllers([_Stepped(ctrl)], compiled=False)).episodes[0]
    assert stepped.summary["steps"] == 1500
    for name in ("pose", "inputs", "outputs", "b", "q", "us_distance", "t"):
        np.testing.assert_array_equal(getattr(stepped.trajectory, name), getattr(compiled, name), err_msg=name)
