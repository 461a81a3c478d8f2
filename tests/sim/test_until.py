"""A run that may stop once its outcome is decided (``EpisodeConfig.until``)."""

from __future__ import annotations

import numpy as np
import pytest

from neurowalk.sim.engines import ENGINES
from neurowalk.sim.episode import EngineOptions, EpisodeConfig, run_episode

ESCAPES = EpisodeConfig(arena="simple-deadlock", controller="static", steps=3000, seed=0)


@pytest.fixture(scope="module")
def both():
    """The same run in full and with until="escaped"."""
    return run_episode(ESCAPES), run_episode(ESCAPES.replace(until="escaped"))


def test_a_run_stops_at_the_first_step_in_the_exit_region(both):
    full, stopped = both
    exit_step = full.summary["exit_step"]
    assert full.summary["escaped"] and exit_step is not None and exit_step < ESCAPES.steps - 1
    assert stopped.summary["steps"] == exit_step + 1 == len(stopped.trajectory.t)
    assert stopped.summary["escaped"] and stopped.summary["exit_step"] == exit_step
    assert stopped.summary["completed"] and stopped.summary["stopped_by"] == "escaped"
    assert stopped.summary["steps_requested"] == ESCAPES.steps
    assert "stopped_by" not in full.summary


def test_stopping_changes_none_of_the_steps_it_ran(both):
    full, stopped = both
    n = stopped.summary["steps"]
    assert np.array_equal(full.trajectory.qpos[:n], stopped.trajectory.qpos)
    assert np.array_equal(full.trajectory.outputs[:n], stopped.trajectory.outputs)


def test_a_run_that_does_not_escape_runs_all_its_steps():
    cfg = EpisodeConfig(arena="simple-deadlock", controller="static", steps=200, seed=0, until="escaped")
    ep = run_episode(cfg)
    assert ep.summary["steps"] == 200 and not ep.summary["escaped"] and "stopped_by" not in ep.summary


def test_until_is_checked_and_keeps_older_keys():
    with pytest.raises(ValueError, match="until must be one of escaped"):
        EpisodeConfig(until="trapped")
    assert EpisodeConfig(until=None).key() == EpisodeConfig().key()  # a later field: absent at its default
    assert EpisodeConfig(until="escaped").key() != EpisodeConfig().key()
    assert EpisodeConfig.from_spec({"until": "escaped"}).until == "escaped"


def test_lock_step_worlds_stop_where_the_cpu_loop_stops(both):
    """mujoco.batch, one call of a world that escapes with one that does not (seed 2), and one of two that escape
    (seed 1, later): each episode ends where the CPU loop's run of its config ends, bit for bit the same steps."""
    _, stopped = both
    runs = {seed: ESCAPES.replace(seed=seed, until="escaped") for seed in (1, 2)}
    refs = {seed: run_episode(cfg) for seed, cfg in runs.items()}
    assert refs[1].summary["stopped_by"] == "escaped" and refs[1].summary["steps"] > stopped.summary["steps"]
    assert "stopped_by" not in refs[2].summary and refs[2].summary["steps"] == ESCAPES.steps
    for other in (1, 2):
        got = ENGINES["mujoco.batch"].run([ESCAPES.replace(until="escaped"), runs[other]], EngineOptions(threads=2))
        for ep, want in zip(got, (stopped, refs[other]), strict=True):
            assert ep.summary["steps"] == want.summary["steps"] and ep.summary["completed"]
            assert ep.summary.get("stopped_by") == want.summary.get("stopped_by")
            assert np.array_equal(ep.trajectory.qpos, want.trajectory.qpos)


def test_a_config_names_mujoco_batch_and_run_episode_runs_it_bit_for_bit():
    cfg = EpisodeConfig(arena="box", steps=40, seed=2)
    batch = run_episode(cfg.replace(engine="mujoco.batch"))
    assert batch.config.engine == "mujoco.batch"
    assert np.array_equal(batch.trajectory.qpos, run_episode(cfg).trajectory.qpos)
