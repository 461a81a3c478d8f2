"""``neurowalk/Explore-v0``: Gymnasium's checks, determinism, the surrogate the networks walk on, bad input."""

from __future__ import annotations

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from neurowalk.arenas import make_arena  # noqa: E402
from neurowalk.body.surrogate import Surrogate  # noqa: E402
from neurowalk.envs import IDS, register_envs  # noqa: E402
from neurowalk.envs.explore import CELL, ExploreEnv  # noqa: E402

register_envs()


@pytest.mark.parametrize("env_id", IDS)
def test_gymnasium_env_checker_passes(env_id):
    env = gym.make(env_id, render_mode="rgb_array", max_steps=50)
    check_env(env.unwrapped)
    env.reset(seed=0)
    env.step(env.action_space.sample())
    frame = env.render()
    assert frame.ndim == 3 and frame.shape[2] == 3 and frame.dtype == np.uint8 and frame.std() > 5
    env.close()


def _episode(seed: int, steps: int = 300) -> tuple[np.ndarray, np.ndarray, list]:
    env = ExploreEnv(max_steps=steps)
    obs, info = env.reset(seed=seed)
    actions = np.random.default_rng(99).uniform(-1, 1, size=(steps, 2))
    observations, rewards, infos = [obs], [], [info]
    for a in actions:
        obs, r, terminated, truncated, info = env.step(a)
        observations.append(obs)
        rewards.append(r)
        infos.append(info)
        assert not terminated
    assert truncated
    return np.array(observations), np.array(rewards), infos


def test_same_seed_same_episode_other_seed_other_environment():
    a, b, c = _episode(4), _episode(4), _episode(5)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
    np.testing.assert_array_equal(a[2][-1]["pose"], b[2][-1]["pose"])
    assert not np.array_equal(a[2][-1]["pose"], c[2][-1]["pose"])


def test_reward_is_the_area_newly_covered():
    env = ExploreEnv(arena="open", max_steps=1500)
    env.reset(seed=0)
    total, cells = 0.0, set()
    for _ in range(1500):
        _, r, _, truncated, info = env.step(np.array([-1.0, -1.0]))  # straight ahead
        total += r
        cells.add(tuple(np.floor(info["pose"][:2] / CELL).astype(int)))
    assert truncated and total > 0
    # every cell entered for the first time paid CELL^2 (the start cell is free); open has no walls
    assert total == pytest.approx(CELL * CELL * (len(cells | {(0, 0)}) - 1))


def test_steering_moves_the_body_as_the_networks_outputs_do():
    env = ExploreEnv(arena="open", max_steps=600, noise=0.0)
    poses = {}
    for name, action in {"ahead": (-1.0, -1.0), "right": (1.0, -1.0), "left": (-1.0, 1.0)}.items():
        _, info = env.reset(seed=1)
        start = info["pose"]
        for _ in range(600):
            _, _, _, _, info = env.step(np.array(action))
        poses[name] = (start, info["pose"])
    (s, e) = poses["ahead"]
    heading = np.array([np.cos(s[2]), np.sin(s[2])])
    assert (e[:2] - s[:2]) @ heading > 0.3  # forward
    turn = {k: np.angle(np.exp(1j * (e[2] - s[2]))) for k, (s, e) in poses.items()}
    assert turn["right"] < -0.5 < 0.5 < turn["left"]  # O1 turns right (clockwise), O2 left


def _step(body: Surrogate, o1: float, o2: float) -> np.ndarray:
    """One control step of the surrogate stepped from Python, as the environment steps it; the pose after it."""
    body.apply(np.array([[o1, o2]]))
    body.advance()
    return body.pose[0].copy()


def test_the_surrogate_one_step_at_a_time_is_its_compiled_run_bit_for_bit():
    arena = make_arena("random", rng=np.random.default_rng(3), n_boxes=12, extent=9.0, size=1.0)
    body = Surrogate(arena)
    run = body.run(400, np.random.default_rng(7), None, None, steer=(-0.3, -1.0))
    body.reset([np.random.default_rng(7)])
    us, poses = [], []
    for _ in range(400):
        us.append(body.sense()[0][0])
        poses.append(_step(body, -0.3, -1.0))
    np.testing.assert_array_equal(np.array(us), run.us)
    np.testing.assert_array_equal(np.array(poses), run.pose)
    assert body.contacts == run.contacts


@pytest.mark.parametrize(
    "action,word",
    [(np.zeros(3), "shape"), (np.array([np.nan, 0.0]), "nan"), (np.array([1.5, 0.0]), "1.5"), ([[0.0, 0.0]], "shape")],
)
def test_bad_action_raises_naming_it(action, word):
    env = ExploreEnv(max_steps=10)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=word):
        env.step(action)


@pytest.mark.parametrize(
    "kwargs,word",
    [({"arena": "maze"}, "maze"), ({"arena": "box", "arena_opts": {"gap": 1}}, "gap"), ({"max_steps": 0}, "max_steps"),
     ({"noise": float("nan")}, "noise"), ({"render_mode": "ascii"}, "ascii"),
     ({"arena_opts": {"n_boxes": 3}}, "arena")],
)  # fmt: skip
def test_bad_settings_raise_naming_them(kwargs, word):
    with pytest.raises(ValueError, match=word):
        ExploreEnv(**kwargs)


def test_step_before_reset_says_so():
    with pytest.raises(RuntimeError, match="reset"):
        ExploreEnv().step(np.zeros(2))


def test_a_network_policy_stepping_the_surrogate_is_the_networks_own_run_bit_for_bit():
    from neurowalk.envs.policy import NetworkPolicy
    from neurowalk.neural.sensory import SensoryNetwork
    from neurowalk.neural.variants import get_variant

    arena = make_arena("random", rng=np.random.default_rng(8), n_boxes=15, extent=9.0, size=1.0)
    body = Surrogate(arena)
    for variant in ("paper", "original"):
        net = SensoryNetwork("plastic", params=get_variant(variant).sensory)
        run = body.run(800, np.random.default_rng(2), net.state, net.packed_params)
        policy = NetworkPolicy("plastic", variant=variant)
        body.reset([np.random.default_rng(2)])
        steer = []
        for _ in range(800):
            seen = body.sense()[0][0]
            obs = np.where(np.isfinite(seen), seen, body.cal.us_range)  # as the environment reports it
            steer.append(policy(obs))
            _step(body, *steer[-1])
        np.testing.assert_array_equal(np.array(steer), run.outputs, err_msg=variant)
        np.testing.assert_array_equal(body.pose[0], run.pose[-1], err_msg=variant)
        assert np.abs(run.outputs).max() > 0.5  # the network did steer


def test_evaluate_scores_networks_on_the_same_environments():
    from neurowalk.envs.policy import NetworkPolicy, evaluate

    a = evaluate(NetworkPolicy("static"), [0, 1], steps=3100)
    b = evaluate(NetworkPolicy("static"), [0, 1], steps=3100)
    assert a == b and a["environments"] == 2 and 0 <= a["success_rate"] <= 1
    assert [r["seed"] for r in a["runs"]] == [0, 1] and all(0 < r["coverage"] < 1 for r in a["runs"])
    with pytest.raises(ValueError, match="wheeled"):
        NetworkPolicy("wheeled")


def test_the_stuck_flag_is_table_2s_rule():
    from neurowalk.envs.task import within_disc
    from neurowalk.metrics import trapped

    rng = np.random.default_rng(0)
    for scale in (0.0005, 0.002, 0.004, 0.01):
        pose = np.cumsum(rng.normal(0, scale, (3000, 3)), axis=0)
        assert within_disc(pose, 0.5) == trapped(pose, window=3000, radius=0.5)
