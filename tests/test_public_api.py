"""The public Python API in one place, and the Gymnasium ids registered by ``import neurowalk`` in either order."""

import subprocess
import sys

import pytest

import neurowalk


def test_the_public_names_load_from_the_package():
    from neurowalk import BODIES, ENGINES, EpisodeConfig, make_arena, make_body, plot_run, run_all, run_episode

    assert set(ENGINES) == {"mujoco", "mujoco.batch", "warp"} and "amosii" in BODIES and "surrogate" in BODIES
    assert callable(run_all) and callable(plot_run)
    ep = run_episode(EpisodeConfig(body="surrogate", arena="corner", steps=50))
    assert ep.summary["steps"] == 50 and ep.trajectory.pose.shape == (50, 3)
    arena = make_arena("corner")
    assert make_body("amosii", arena).action == "targets"
    for name in neurowalk.__all__:
        assert getattr(neurowalk, name) is not None, name


def _python(code: str) -> str:
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


@pytest.mark.parametrize(
    "how",
    [
        "import neurowalk.envs, gymnasium\nid = 'neurowalk/Explore-v0'",
        "import gymnasium, neurowalk.envs\nid = 'neurowalk/Explore-v0'",
        "import gymnasium\nid = 'neurowalk.envs:neurowalk/Explore-v0'",  # Gymnasium's module prefix imports it
    ],
)
def test_gymnasium_makes_the_environments_by_either_of_its_two_ways(how):
    pytest.importorskip("gymnasium")
    out = _python(
        f"{how}\n"
        "env = gymnasium.make(id)\n"
        "obs, _ = env.reset(seed=0)\n"
        "print(obs.shape, 'neurowalk/ExplorePhysics-v0' in gymnasium.registry)"
    )
    assert out == "(2,) True"


def test_import_neurowalk_has_no_side_effect_on_the_import_system_or_numba():
    """No import hook, no numba setting changed by importing neurowalk or a kernel module of plain kernels."""
    code = (
        "import sys, numba\n"
        "hooks, layer = len(sys.meta_path), numba.config.THREADING_LAYER\n"
        "import neurowalk, neurowalk.neural.sensory\n"
        "print(len(sys.meta_path) == hooks, numba.config.THREADING_LAYER == layer)"
    )
    assert _python(code) == "True True"


def test_import_neurowalk_does_not_import_gymnasium_or_the_simulation():
    out = _python(
        "import sys, neurowalk; print(sorted(m for m in ('gymnasium', 'mujoco', 'numba') if m in sys.modules))"
    )
    assert out == "[]"
