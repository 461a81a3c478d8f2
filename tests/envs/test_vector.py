"""``neurowalk/Explore-v0`` vectorised: the single environment's copies, independent, with next-step autoreset."""

from __future__ import annotations

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")

import neurowalk.envs  # noqa: E402,F401  (registers the ids)
from neurowalk.envs.explore import CELL, ExploreEnv  # noqa: E402
from neurowalk.envs.vector import ExploreVectorEnv  # noqa: E402


def _vec(n: int, **kw):
    return gym.make_vec("neurowalk/Explore-v0", num_envs=n, vectorization_mode="vector_entry_point", **kw)


def _actions(n: int, steps: int) -> np.ndarray:
    return np.random.default_rng(5).uniform(-1, 1, size=(steps, n, 2))


def test_make_vec_gives_the_compiled_vector_env_with_batched_spaces():
    env = _vec(3, max_steps=50)
    assert isinstance(env.unwrapped, ExploreVectorEnv) and env.num_envs == 3
    obs, info = env.reset(seed=0)
    assert obs.shape == (3, 2) and env.observation_space.contains(obs) and info["pose"].shape == (3, 3)
    obs, r, term, trunc, info = env.step(env.action_space.sample())
    assert env.observation_space.contains(obs) and r.shape == term.shape == trunc.shape == (3,)


def test_without_noise_each_copy_is_the_single_environment_bit_for_bit():
    n, steps = 3, 400
    vec = ExploreVectorEnv(n, max_steps=steps, noise=0.0)
    obs_v, _ = vec.reset(seed=10)
    acts = _actions(n, steps)
    out_v = [obs_v]
    for a in acts:
        out_v.append(vec.step(a)[0])
    out_v = np.array(out_v)
    for i in range(n):
        single = ExploreEnv(max_steps=steps, noise=0.0)
        obs, _ = single.reset(seed=10 + i)
        out = [obs]
        for a in acts[:, i]:
            out.append(single.step(a)[0])
            pose = single._body.pose[0]
        np.testing.assert_array_equal(np.array(out), out_v[:, i], err_msg=f"copy {i}")
        np.testing.assert_array_equal(pose, vec.pose[i])


def test_a_copy_depends_on_its_own_seed_only():
    acts = _actions(4, 300)
    big, small = ExploreVectorEnv(4, max_steps=300), ExploreVectorEnv(1, max_steps=300)
    big.reset(seed=[7, 8, 9, 10])
    small.reset(seed=[9])
    for a in acts:
        ob, _, _, _, ib = big.step(a)
        os_, _, _, _, is_ = small.step(a[2:3])
        np.testing.assert_array_equal(ob[2], os_[0])
    np.testing.assert_array_equal(ib["pose"][2], is_["pose"][0])


def test_next_step_autoreset_and_rewards_are_new_area():
    env = ExploreVectorEnv(2, max_steps=5)
    env.reset(seed=1)
    for _ in range(5):
        obs, r, term, trunc, _ = env.step(np.full((2, 2), -1.0))
    assert trunc.all() and not term.any()
    first = env.boxes.copy()
    obs, r, term, trunc, _ = env.step(np.full((2, 2), 1.0))  # ignored: the copies start anew
    assert (r == 0).all() and not trunc.any() and (env.ks == 0).all() and not np.array_equal(env.boxes, first)
    assert env.observation_space.contains(obs)


def test_reward_sums_to_the_cells_entered():
    env = ExploreVectorEnv(3, max_steps=2000)
    env.reset(seed=4)
    total = np.zeros(3)
    for a in _actions(3, 1500):
        total += env.step(a)[1]
    cells = env.visited.reshape(3, -1).sum(axis=1)
    np.testing.assert_allclose(total, CELL * CELL * (cells - 1))
    assert (env.covered <= cells).all() and (env.covered > 1).all()


@pytest.mark.parametrize("actions,word", [(np.zeros((3, 2)), "shape"), (np.full((2, 2), np.nan), "nan"),
                                          (np.array([[0.0, 0.0], [2.0, 0.0]]), "2.0")])  # fmt: skip
def test_bad_actions_raise_naming_them(actions, word):
    env = ExploreVectorEnv(2, max_steps=10)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=word):
        env.step(actions)


@pytest.mark.parametrize("kwargs,word", [({"num_envs": 0}, "num_envs"), ({"arena": "open"}, "bounded"),
                                         ({"arena": "maze"}, "maze")])  # fmt: skip
def test_bad_settings_raise_naming_them(kwargs, word):
    with pytest.raises(ValueError, match=word):
        ExploreVectorEnv(**kwargs).reset(seed=0)


def test_the_coverage_grid_is_the_arenas_free_cells():
    from neurowalk.arenas import make_arena
    from neurowalk.body.surrogate import box_rows
    from neurowalk.envs.vector_kernel import free_mask

    for seed in range(5):
        arena = make_arena("random", rng=np.random.default_rng(seed), n_boxes=20, extent=9.0, size=1.0)
        x0, x1, y0, y1 = arena.bounds
        rows = box_rows(arena)
        nx, ny = len(np.arange(x0 + CELL / 2, x1, CELL)), len(np.arange(y0 + CELL / 2, y1, CELL))
        out = np.zeros((nx, ny), dtype=bool)
        free_mask(rows, len(rows), x0, y0, CELL, nx, ny, out)
        centres = arena.free_cells(CELL)
        expected = np.zeros_like(out)
        idx = np.floor((centres - (x0, y0)) / CELL).astype(int)
        expected[idx[:, 0], idx[:, 1]] = True
        np.testing.assert_array_equal(out, expected)
