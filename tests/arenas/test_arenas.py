"""Contract tests over every registered arena: builds, compiles, steps finitely, deterministic."""

import numpy as np
import pytest

from neurowalk.arenas import ARENAS, arena_options, make_arena
from neurowalk.sim.episode import EpisodeConfig, run_episode


@pytest.mark.parametrize("name", sorted(ARENAS))
def test_every_arena_compiles_runs_finite_and_deterministic(name):
    a = run_episode(EpisodeConfig(arena=name, controller="plastic", steps=60, seed=1))
    b = run_episode(EpisodeConfig(arena=name, controller="plastic", steps=60, seed=1))
    assert np.all(np.isfinite(a.trajectory.qpos))
    np.testing.assert_array_equal(a.trajectory.qpos, b.trajectory.qpos)
    assert a.summary["arena_opts"] == arena_options(name)


def test_bad_options_are_named():
    with pytest.raises(ValueError, match="no option 'gap'"):
        make_arena("box", gap=1)
    with pytest.raises(ValueError, match="distance"):
        make_arena("box", distance=0.1)
    with pytest.raises(ValueError, match="not a float"):
        make_arena("box", width="wide")
    with pytest.raises(ValueError, match="unknown arena"):
        make_arena("maze")


def test_box_geometry():
    spec = make_arena("box", distance=1.0, width=0.8)
    (box,) = spec.boxes
    assert box.x - box.sx / 2 == pytest.approx(1.0)
    assert box.contains(np.array([[1.1, 0.39]]))[0] and not box.contains(np.array([[1.1, 0.41]]))[0]
