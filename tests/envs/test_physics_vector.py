"""``neurowalk/ExplorePhysics-v0`` vectorised: each copy is the single environment bit for bit, next-step autoreset."""

from __future__ import annotations

import copy

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")

from gymnasium.utils.seeding import np_random  # noqa: E402

import neurowalk.envs  # noqa: E402,F401  (registers the ids)
from neurowalk.envs.physics import ExplorePhysicsEnv  # noqa: E402
from neurowalk.envs.physics_vector import ExplorePhysicsVectorEnv  # noqa: E402
from neurowalk.envs.task import within_disc  # noqa: E402
from neurowalk.envs.vector_kernel import count_cells  # noqa: E402


def _actions(env: ExplorePhysicsVectorEnv, steps: int, seed: int = 5) -> np.ndarray:
    space = env.single_action_space
    return np.random.default_rng(seed).uniform(space.low, space.high, size=(steps, env.num_envs, *space.shape))


def _run_vector(env: ExplorePhysicsVectorEnv, seed, acts: np.ndarray) -> list[tuple]:
    """(obs, reward, truncated, info) after reset (reward 0, not truncated) and after each step."""
    obs, info = env.reset(seed=seed)
    out = [(obs, np.zeros(env.num_envs), np.zeros(env.num_envs, dtype=bool), info)]
    for a in acts:
        obs, r, term, trunc, info = env.step(a)
        assert not term.any()
        out.append((obs, r, trunc, info))
    return out


def _assert_copy_is_single(out: list[tuple], i: int, single: ExplorePhysicsEnv, seed: int, acts: np.ndarray) -> None:
    obs, info = single.reset(seed=seed)
    rows = [(obs, 0.0, False, info)] + [(o, r, tr, inf) for o, r, _, tr, inf in (single.step(a) for a in acts)]
    for k, ((o, r, tr, inf), (ov, rv, trv, iv)) in enumerate(zip(rows, out, strict=True)):
        where = f"copy {i}, step {k}"
        np.testing.assert_array_equal(o, ov[i], err_msg=where)
        np.testing.assert_array_equal(inf["pose"], iv["pose"][i], err_msg=where)
        assert (r, tr, inf["contacts"], inf["stuck"]) == (rv[i], trv[i], iv["contacts"][i], iv["stuck"][i]), where
        np.testing.assert_array_equal(inf["coverage"], iv["coverage"][i], err_msg=where)  # NaN == NaN here


@pytest.mark.parametrize("action", ["steering", "joints"])
def test_each_copy_is_the_single_environment_bit_for_bit(action):
    steps = 30
    vec = ExplorePhysicsVectorEnv(2, max_steps=steps, action=action)
    acts = _actions(vec, steps)
    out = _run_vector(vec, 10, acts)
    assert out[-1][2].all() and out[-1][3]["coverage"].min() > 0  # truncated at the end, cells covered
    for i in range(2):
        _assert_copy_is_single(out, i, ExplorePhysicsEnv(max_steps=steps, action=action), 10 + i, acts[:, i])


def test_obstacle_contacts_are_the_single_environments():
    # walking straight into a box 0.3 m ahead: the first contact comes at about step 94 (tests/sim/test_batch.py);
    # an unbounded arena, so the cells are counted off the grid and coverage is NaN
    steps, kw = 110, {"arena": "box", "arena_opts": {"distance": 0.3}}
    vec = ExplorePhysicsVectorEnv(2, max_steps=steps, **kw)
    acts = np.full((steps, 2, 2), -1.0)
    out = _run_vector(vec, [3, 4], acts)
    assert (out[-1][3]["contacts"] > 0).all() and np.isnan(out[-1][3]["coverage"]).all()
    for i in range(2):
        _assert_copy_is_single(out, i, ExplorePhysicsEnv(max_steps=steps, **kw), 3 + i, acts[:, i])


def test_next_step_autoreset_starts_the_single_environment_of_a_drawn_seed():
    steps, more = 8, 6
    vec = ExplorePhysicsVectorEnv(2, max_steps=steps)
    acts = _actions(vec, steps + 1 + more)
    out = _run_vector(vec, 20, acts)
    assert out[steps][2].all()
    _, r, trunc, info = out[steps + 1]  # the step after the last: new episodes, its action ignored
    assert (r == 0).all() and not trunc.any() and (info["contacts"] == 0).all() and (vec.ks == more).all()
    rng, _ = np_random(20)  # the vector environment's generator after reset(seed=20): the new seeds
    for i, seed in enumerate(int(rng.integers(2**62)) for _ in range(2)):
        _assert_copy_is_single(out[steps + 1 :], i, ExplorePhysicsEnv(max_steps=steps), seed, acts[steps + 1 :, i])


def test_restarting_one_copy_leaves_the_others_alone():
    steps = 20
    vec = ExplorePhysicsVectorEnv(3, max_steps=steps)
    acts = _actions(vec, steps)
    obs, info = vec.reset(seed=30)
    out = [(obs, np.zeros(3), np.zeros(3, dtype=bool), info)]
    for k, a in enumerate(acts):
        if (
            k == 7
        ):  # copy 1's episode ends here: the next step starts its new one (autoreset), mid-episode of the others
            vec.done[1] = True
            seed = int(copy.deepcopy(vec.np_random).integers(2**62))  # the seed the environment draws for it
        obs, r, _, trunc, info = vec.step(a)
        out.append((obs, r, trunc, info))
    for i in (0, 2):
        _assert_copy_is_single(out, i, ExplorePhysicsEnv(max_steps=steps), 30 + i, acts[:, i])
    assert out[8][1][1] == 0.0  # the step that restarts it: its first observation, reward 0 (its action unused)
    _assert_copy_is_single(out[8:], 1, ExplorePhysicsEnv(max_steps=steps), seed, acts[8:, 1])


def test_make_vec_gives_the_vector_env_with_batched_spaces_and_is_deterministic():
    def run() -> tuple:
        env = gym.make_vec("neurowalk/ExplorePhysics-v0", num_envs=2, vectorization_mode="vector_entry_point",
                           max_steps=10)  # fmt: skip
        assert isinstance(env.unwrapped, ExplorePhysicsVectorEnv) and env.num_envs == 2
        obs, info = env.reset(seed=0)
        assert env.observation_space.contains(obs) and info["pose"].shape == (2, 3) and info["stuck"].shape == (2,)
        env.action_space.seed(1)
        rows = [env.step(env.action_space.sample()) for _ in range(5)]
        assert all(env.observation_space.contains(row[0]) and row[1].shape == (2,) for row in rows)
        return np.array([row[0] for row in rows]), np.array([row[4]["pose"] for row in rows])

    a, b = run(), run()
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


@pytest.mark.parametrize("actions,word", [(np.zeros((3, 2)), r"\(2, 2\)"), (np.full((2, 2), np.nan), "nan"),
                                          (np.array([[0.0, 0.0], [2.0, 0.0]]), "2.0"),
                                          (np.zeros((2, 19)), r"\(2, 19\)")])  # fmt: skip
def test_bad_actions_raise_naming_them(actions, word):
    env = ExplorePhysicsVectorEnv(2, max_steps=10)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=word):
        env.step(actions)


@pytest.mark.parametrize("kwargs,word", [({"num_envs": 0}, "num_envs"), ({"nthread": 0}, "nthread"),
                                         ({"action": "torques"}, "torques"), ({"arena": "maze"}, "maze"),
                                         ({"max_steps": 0}, "max_steps")])  # fmt: skip
def test_bad_settings_raise_naming_them(kwargs, word):
    with pytest.raises(ValueError, match=word):
        ExplorePhysicsVectorEnv(**{"num_envs": 1, **kwargs})


def test_the_stuck_flag_is_within_disc_of_the_last_window():
    n, w, steps = 2, 5, 40
    walk = np.cumsum(np.random.default_rng(2).normal(0.0, 0.05, size=(steps + 1, n, 2)), axis=0)
    ring, ks = np.zeros((n, w, 2)), np.zeros(n, dtype=np.int64)
    ring[:, 0] = walk[0]
    grid = np.zeros((n, 4, 4), dtype=bool)
    pose, ids = np.zeros((n, 3)), np.arange(n)
    flags = []
    for k in range(1, steps + 1):
        pose[:, :2] = walk[k]
        stuck = np.zeros(n, dtype=bool)
        count_cells(ids, pose, np.zeros((n, 2)), 0.25, grid, grid.copy(), np.zeros(n, dtype=np.int64), ks,
                    np.zeros(n), np.zeros(n, dtype=bool), ring, 0.1, stuck)  # fmt: skip
        expected = [k + 1 >= w and within_disc(walk[k + 1 - w : k + 1, i], 0.1) for i in range(n)]
        assert stuck.tolist() == expected
        flags.append(stuck.copy())
    assert 0 < np.sum(flags) < n * steps  # both answers seen
