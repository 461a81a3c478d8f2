"""``neurowalk/ExplorePhysics-v0``: Gymnasium's checks, the networks' locomotion, joint actions, bad input."""

from __future__ import annotations

import contextlib

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

import neurowalk.envs  # noqa: E402,F401  (registers the ids)
from neurowalk.envs.physics import ExplorePhysicsEnv  # noqa: E402


@pytest.mark.parametrize("action", ["steering", "joints"])
def test_gymnasium_env_checker_passes(action):
    env = gym.make("neurowalk/ExplorePhysics-v0", action=action, max_steps=20, render_mode="rgb_array")
    hint = pytest.warns(UserWarning, match="symmetric") if action == "joints" else contextlib.nullcontext()
    with hint:  # joint ranges are the actuators' own, not [-1, 1]: Gymnasium's checker says so
        check_env(env.unwrapped)
    env.reset(seed=0)
    env.step(env.action_space.sample())
    frame = env.render()
    assert frame.shape == (480, 640, 3) and frame.dtype == np.uint8 and frame.std() > 5
    env.close()


def test_steering_through_the_locomotion_network_walks_and_turns():
    env = ExplorePhysicsEnv(arena="open", max_steps=400, noise=0.0)
    ends = {}
    for name, action in {"ahead": (-1.0, -1.0), "right": (1.0, -1.0)}.items():
        _, info = env.reset(seed=0)
        start = info["pose"]
        for _ in range(400):
            _, _, _, truncated, info = env.step(np.array(action))
        assert truncated
        ends[name] = (start, info["pose"])
    s, e = ends["ahead"]
    assert (e[:2] - s[:2]) @ np.array([np.cos(s[2]), np.sin(s[2])]) > 0.1  # forward, 40 s of the wave gait
    s, e = ends["right"]
    assert np.angle(np.exp(1j * (e[2] - s[2]))) < -0.3  # O1 turns right (clockwise)


def test_same_seed_same_episode():
    def run() -> np.ndarray:
        env = ExplorePhysicsEnv(max_steps=60)
        obs, _ = env.reset(seed=3)
        out = [obs]
        for a in np.random.default_rng(1).uniform(-1, 1, size=(60, 2)):
            out.append(env.step(a)[0])
        return np.array(out)

    np.testing.assert_array_equal(run(), run())


@pytest.mark.parametrize(
    "kwargs,word",
    [({"action": "torques"}, "torques"), ({"max_steps": -1}, "max_steps"), ({"control_hz": 0}, "control_hz")],
)
def test_bad_settings_raise_naming_them(kwargs, word):
    with pytest.raises(ValueError, match=word):
        ExplorePhysicsEnv(**kwargs)


def test_joint_actions_outside_the_actuator_ranges_are_refused():
    env = ExplorePhysicsEnv(action="joints", max_steps=5)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="bounds"):
        env.step(env.action_space.high + 1.0)
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(2))


def test_the_real_robots_control_rate_steps_its_clock():
    """At 27 Hz a step is 1/27 s of physics (7 steps of 5.29 ms), and the robot walks more per second than at 10."""
    moved = {}
    for hz in (10.0, 27.0):
        env = ExplorePhysicsEnv(arena="open", max_steps=400, control_hz=hz)
        env.reset(seed=0)
        for _ in range(400):
            env.step(np.array([-1.0, -1.0]))
        assert env.body.data.time == pytest.approx(400 / hz)
        x, y = env.body.data.qpos[:2]
        moved[hz] = np.hypot(x - env.body.arena.start[0], y - env.body.arena.start[1]) / env.body.data.time
    assert moved[27.0] > 1.5 * moved[10.0]  # the networks keep their steps: more steps a second, faster walking


def test_importing_the_environments_chooses_no_gl_backend_rendering_does(tmp_path):
    """`import neurowalk.envs` registers the ids and nothing else; an rgb_array render without a display chooses
    EGL where it starts, MuJoCo imported before or not."""
    import os
    import subprocess
    import sys

    code = (
        "import os, gymnasium, neurowalk.envs\n"
        "assert 'MUJOCO_GL' not in os.environ, os.environ.get('MUJOCO_GL')\n"
        "env = gymnasium.make('neurowalk/ExplorePhysics-v0', max_steps=5, render_mode='rgb_array')\n"
        "env.reset(seed=0)\n"
        "frame = env.render()\n"
        "print(frame.shape, int(frame.std() > 5), os.environ['MUJOCO_GL'])\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "MUJOCO_GL")}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == "(480, 640, 3) 1 egl"
