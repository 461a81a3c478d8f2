"""Table 2's environment i is one arena and start wherever it is asked for: from the public function, in the figure's
runs, and in each Gymnasium exploration environment reset onto it (``options={"table2": i}``)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import neurowalk
import neurowalk.envs  # registers the ids
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.study import planned, resolve
from neurowalk.experiments.suites.random_envs import arena_of
from neurowalk.sim.table2 import table2_arena, table2_config, table2_environments

ENVS = (0, 3, 7)


def _layout(arena) -> tuple:
    """What makes an arena the same: its boxes (centre, size, yaw) and its start pose."""
    boxes = tuple(tuple(np.round([b.x, b.y, b.sx, b.sy, b.h, b.yaw], 12)) for b in arena.boxes)
    return boxes, tuple(np.round(arena.start, 12))


def _figure_arenas() -> dict[int, tuple]:
    """The arena of each of the quick figure's environments, from its plans."""
    s = resolve(FIGURES["table2"], Settings(quick=True))
    out = {}
    for plan in planned(FIGURES["table2"], s):
        cfg = plan.config
        if cfg.body == "surrogate" and cfg.controller == "plastic":
            out.setdefault(cfg.seed, _layout(arena_of(cfg.spec())))
    return out


def test_the_public_function_is_the_figures_environments():
    assert neurowalk.table2_environments is table2_environments and neurowalk.table2_config is table2_config
    envs = table2_environments(10)
    assert [e["seed"] for e in envs] == list(range(10)) and all(2 <= e["n_boxes"] <= 20 for e in envs)
    assert len({e["n_boxes"] for e in envs}) > 1  # drawn, not one count
    figure = _figure_arenas()
    assert sorted(figure) == list(range(10))  # the quick figure runs environments 0..9
    for i in ENVS:
        assert figure[i] == _layout(table2_arena(i)) == _layout(arena_of(table2_config(i, body="surrogate").spec()))
    assert _layout(table2_arena(1)) != _layout(table2_arena(2))


@pytest.mark.parametrize("env_id", ["neurowalk/Explore-v0", "neurowalk/ExplorePhysics-v0"])
def test_a_gymnasium_environment_reset_onto_environment_i_has_its_arena_and_start(env_id):
    env = gym.make(env_id)
    try:
        for i in ENVS:
            _, info = env.reset(seed=99, options={"table2": i})
            assert _layout(env.unwrapped.arena) == _layout(table2_arena(i))
            assert np.allclose(info["pose"], table2_arena(i).start, atol=0.02)  # the body at the table's start
        env.reset(seed=99)  # without the option: a layout of its own seed
        assert _layout(env.unwrapped.arena) != _layout(table2_arena(0))
        with pytest.raises(ValueError, match="table2"):
            env.reset(options={"table2": -1})
    finally:
        env.close()


@pytest.mark.parametrize("env_id", ["neurowalk/Explore-v0", "neurowalk/ExplorePhysics-v0"])
def test_a_vector_environment_puts_copy_k_in_environment_i_plus_k(env_id):
    env = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point")
    try:
        _, info = env.reset(seed=5, options={"table2": 3})
        for k in (0, 1):
            assert np.allclose(info["pose"][k], table2_arena(3 + k).start, atol=0.02)
        _, info = env.reset(seed=5, options={"table2": [7, 0]})
        assert np.allclose(info["pose"][0], table2_arena(7).start, atol=0.02)
        assert np.allclose(info["pose"][1], table2_arena(0).start, atol=0.02)
    finally:
        env.close()
