"""A streamed run (``keep_rows=False``): memory bounded by the chunk, the same rows and summary as in memory."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from neurowalk.sim.checkpoint import Checkpoint
from neurowalk.sim.episode import EpisodeConfig, Resume, RunInterruptedError, Streaming, run_episode
from neurowalk.sim.trajectory import PartWriter, Trajectory

VOLATILE = ("wall_time_s", "real_time_factor", "resumed_at_step")


def _same_summary(a: dict, b: dict) -> None:
    assert {k: v for k, v in a.items() if k not in VOLATILE} == {k: v for k, v in b.items() if k not in VOLATILE}


def _same_rows(a: Trajectory, b: Trajectory) -> None:
    assert a.arrays().keys() == b.arrays().keys()
    for name, col in a.arrays().items():
        np.testing.assert_array_equal(col, b.arrays()[name], err_msg=name)


def test_streamed_run_writes_every_row_and_summarises_as_in_memory(tmp_path, monkeypatch):
    # Pushing into a box for 130 s: a wedged period whose contacts are replayed from the parts on disk.
    cfg = EpisodeConfig(arena="box", arena_opts={"distance": 0.3}, controller="fixed", steer=(-1, -1), steps=1300)
    whole = run_episode(cfg)
    parts = PartWriter(tmp_path / "parts")
    streamed = run_episode(
        cfg, stream=Streaming(sink=parts, chunk=300, keep_rows=False, picture_rows=100)
    )  # every 13th
    assert whole.summary["wedged_causes"] == {"body contact": 1}
    _same_summary(streamed.summary, whole.summary)
    n = parts.join(tmp_path / "trajectory.npz")
    assert n == 1300
    _same_rows(Trajectory.load(tmp_path / "trajectory.npz"), whole.trajectory)
    assert streamed.row_stride == 13 and len(streamed.trajectory) == 100
    _same_rows(streamed.trajectory, _every(whole.trajectory, 13))


def _every(tr: Trajectory, k: int) -> Trajectory:
    return tr.map(lambda v: v[::k])


def test_streamed_run_stopped_and_resumed_from_its_parts_is_the_whole_run(tmp_path):
    cfg = EpisodeConfig(arena="box", arena_opts={"distance": 0.6}, steps=700, seed=2)
    whole = run_episode(cfg)
    parts = PartWriter(tmp_path / "parts")
    saved: dict[int, Checkpoint] = {}

    def stop_after_third(rows: Trajectory, start: int) -> None:
        parts(rows, start)
        if start == 400 and not stopped:
            stopped.append(start)
            raise KeyboardInterrupt  # Ctrl-C while writing the third part: written again at the stop

    stopped: list[int] = []

    with pytest.raises(RunInterruptedError) as info:
        run_episode(
            cfg,
            stream=Streaming(
                sink=stop_after_third, chunk=200, keep_rows=False, checkpoint=lambda c: saved.setdefault(c.step, c)
            ),
        )
    assert info.value.episode.summary["steps"] == 600 and sorted(saved) == [200, 400]
    resumed = run_episode(
        cfg, stream=Streaming(sink=parts, chunk=200, keep_rows=False, resume=Resume(saved[400], parts.pieces()))
    )
    _same_summary(resumed.summary, whole.summary)
    assert resumed.summary["resumed_at_step"] == 400 and "resumed_at_step" not in whole.summary
    assert parts.join(tmp_path / "t.npz") == 700
    _same_rows(Trajectory.load(tmp_path / "t.npz"), whole.trajectory)


def test_streamed_memory_is_bounded_by_the_chunk_not_the_run(tmp_path, monkeypatch):
    cfg = EpisodeConfig(arena="open", controller="fixed", steer=(1, 1), steps=2000)
    run_episode(EpisodeConfig(arena="open", controller="fixed", steer=(1, 1), steps=5))  # compile, load
    peaks = {}
    for keep in (True, False):
        tracemalloc.start()
        run_episode(cfg, stream=Streaming(sink=lambda rows, start: None, chunk=100, keep_rows=keep, picture_rows=100))
        peaks[keep] = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    row_bytes = sum(8 * int(np.prod(v.shape)) for v in Trajectory.empty(1, 26).arrays().values())
    assert peaks[True] > 2000 * row_bytes  # every row in memory
    assert peaks[False] < 0.35 * peaks[True]  # one chunk, the summary's 72 bytes a step, a picture


def test_keep_rows_false_needs_a_sink():
    with pytest.raises(ValueError, match="sink"):
        run_episode(EpisodeConfig(steps=5), stream=Streaming(keep_rows=False))


@pytest.mark.parametrize("body", ["surrogate", "surrogate-wheeled"])
def test_a_streamed_planar_run_writes_every_row_and_summarises_as_in_memory(body, tmp_path, monkeypatch):
    cfg = EpisodeConfig(arena="cluttered", body=body, steps=2300, seed=3)
    whole = run_episode(cfg)
    parts = PartWriter(tmp_path / "parts")
    streamed = run_episode(cfg, stream=Streaming(sink=parts, chunk=500, keep_rows=False, picture_rows=100))
    _same_summary(streamed.summary, whole.summary)
    assert parts.join(tmp_path / "trajectory.npz") == 2300
    _same_rows(Trajectory.load(tmp_path / "trajectory.npz"), whole.trajectory)
    assert streamed.row_stride == 23 and len(streamed.trajectory) == 100
    _same_rows(streamed.trajectory, _every(whole.trajectory, 23))


@pytest.mark.parametrize("body", ["amosii", "surrogate"])
@pytest.mark.parametrize("keep_rows", [True, False])
def test_a_run_stopped_in_its_sink_counts_the_rows_on_disk(body, keep_rows, tmp_path):
    """Ctrl-C while a part is written: the summary's steps are the rows the parts hold."""
    cfg = EpisodeConfig(arena="box", body=body, steps=900, seed=1)
    parts = PartWriter(tmp_path / "parts")
    seen: list[int] = []

    def stop_in_the_third(rows: Trajectory, start: int) -> None:
        seen.append(start)
        if len(seen) == 3:
            raise KeyboardInterrupt
        parts(rows, start)

    with pytest.raises(RunInterruptedError) as info:
        run_episode(cfg, stream=Streaming(sink=stop_in_the_third, chunk=200, keep_rows=keep_rows))
    ep = info.value.episode
    assert ep.summary["steps"] == parts.count() and not ep.summary["completed"]
    if keep_rows:
        assert len(ep.trajectory) == parts.count()
