"""``Streaming.stop``: a run asked to stop as it goes (a command's ``stop_requested``: a stop signal whose
KeyboardInterrupt a library swallowed) ends there as a Ctrl-C would: the completed steps kept, none changed."""

from __future__ import annotations

import numpy as np
import pytest

from neurowalk.runners.specs import episode_of
from neurowalk.sim.episode import EpisodeConfig, RunInterruptedError, Streaming, run_episode

RUNS = {
    "amosii": EpisodeConfig(arena="cluttered", steps=600, seed=3),  # asked every 100 steps
    "surrogate": EpisodeConfig(body="surrogate", arena="cluttered", steps=600, seed=3),  # at every chunk's end
}
KEPT = {"amosii": 300, "surrogate": 200}  # asked a third time: after step 300; before the third chunk is handed on


def _asked_until(n: int):
    """A stop() that answers True from its ``n``-th call on; the calls it got."""
    calls: list[int] = []

    def stop() -> bool:
        calls.append(1)
        return len(calls) >= n

    return stop, calls


@pytest.mark.parametrize("body", sorted(RUNS))
def test_a_run_asked_to_stop_keeps_its_completed_steps_unchanged(body):
    cfg = RUNS[body]
    full = run_episode(cfg)
    stop, calls = _asked_until(3)
    with pytest.raises(RunInterruptedError) as e:
        run_episode(cfg, stream=Streaming(chunk=100, stop=stop))
    part = e.value.episode
    n = part.summary["steps"]
    assert len(calls) == 3
    assert n == KEPT[body] == len(part.trajectory.t)
    assert np.array_equal(full.trajectory.pose[:n], part.trajectory.pose)
    assert np.array_equal(full.trajectory.outputs[:n], part.trajectory.outputs)


def test_a_run_never_asked_to_stop_runs_all_its_steps():
    cfg = RUNS["surrogate"]
    stop, calls = _asked_until(10**9)
    ep = run_episode(cfg, stream=Streaming(chunk=100, stop=stop))
    assert ep.summary["steps"] == cfg.steps and len(calls) == cfg.steps // 100


def test_a_sweeps_run_asks_whether_a_stop_came(monkeypatch):
    from neurowalk.runners import specs

    stop, calls = _asked_until(2)
    monkeypatch.setattr(specs, "stop_requested", stop)
    with pytest.raises(KeyboardInterrupt):
        episode_of(RUNS["surrogate"].spec(), stream=Streaming(chunk=100))
    assert len(calls) == 2
