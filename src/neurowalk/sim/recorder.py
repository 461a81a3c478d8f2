"""The one recorder of a run's rows and the one episode finisher, for every engine.

:class:`Recorder` is where the loop (:mod:`neurowalk.sim.loop`) writes the rows of its worlds: the whole run in
memory, or one chunk at a time handed to a sink, keeping only the summary's columns
(:class:`~neurowalk.sim.summarize.RecordKeeper`). :func:`finish_episode` turns the rows of any engine's run (the
loop's worlds, the surrogate) into its :class:`Episode`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from neurowalk import profiling
from neurowalk.arenas import ArenaSpec
from neurowalk.body.world import CompiledWorld, World
from neurowalk.sim.config import Episode, EpisodeConfig
from neurowalk.sim.engine_interface import Streaming
from neurowalk.sim.summarize import Record, RecordKeeper, summarize
from neurowalk.sim.trajectory import STATE, Trajectory, poses_from_qpos, up_z_from_qpos

__all__ = ["Recorder", "derive_columns", "finish_episode"]


class Recorder:
    """Where the loop writes the rows of n worlds: the whole run in memory, or (one world) one chunk at a time
    (``keep_rows=False``).

    ``cols`` holds each column as an (n, rows, ...) array, world-major, so that world w's rows (``worlds[w]``, a
    :class:`Trajectory` of views) are contiguous; the rows are the steps from ``base`` on. A column the world does
    not fill (``world.columns``: a planar body has no joints) is a read-only NaN view taking no memory (``up_z``:
    1). :meth:`flush` completes the rows written since the last flush (derived columns), hands world 0's to the
    sink, copies the summary's columns and the picture's rows out of a chunk buffer and starts the buffer again.
    Many worlds keep every row (no sink, no chunks).
    """

    def __init__(
        self,
        steps: int,
        world: World | CompiledWorld,
        stream: Streaming,
        start: int,
        state: Mapping[str, tuple[int, ...]] | None = None,
    ) -> None:
        sink, keep_rows = stream.sink, stream.keep_rows
        if world.n > 1 and (sink is not None or not keep_rows):
            raise ValueError("the rows of many worlds are kept in memory: no sink, keep_rows=True")
        self.sink, self.keep_rows, self.qidx = sink, keep_rows, world.qidx
        self.chunk = stream.chunk if sink is not None or not keep_rows else steps
        self.flushed = start
        nq = world.nq
        rows = steps if keep_rows else self.chunk
        self.derived = nq > 0  # pose, joint angles and up_z from qpos (else the world's own pose; upright)
        self.cols = {
            k: np.full((world.n, rows, *s), np.nan)
            if k in world.columns
            else _constant(1.0 if k == "up_z" else math.nan, (world.n, rows, *s))  # read-only: no memory
            for k, s in Trajectory.shapes(nq).items()
        }
        self.state = {STATE + k: np.full((world.n, rows, *s), np.nan) for k, s in (state or {}).items()}
        self.cols.update(self.state)
        self.worlds = [Trajectory.from_arrays({k: a[w] for k, a in self.cols.items()}) for w in range(world.n)]
        self.buf = self.worlds[0]
        self.base = 0 if keep_rows else start
        self.keeper = None if keep_rows else RecordKeeper(steps, nq, stream.picture_rows, state)
        self.stride = 1 if self.keeper is None else self.keeper.stride

    def done(self) -> int:
        """Steps completed (rows with a time)."""
        return self.base + int(np.count_nonzero(~np.isnan(self.buf.t)))

    def restore(self, head: Trajectory | Iterable[tuple[int, Trajectory]]) -> None:
        """Take the rows before a resumed run's first step (a trajectory, or (start, rows) pieces in order)."""
        n = self.flushed
        for start, rows in [(0, head)] if isinstance(head, Trajectory) else head:
            stop = min(start + len(rows), n)
            if stop <= start:
                continue
            if self.keep_rows:
                mine = self.buf.arrays()
                for k, v in rows.arrays().items():
                    mine[k][start:stop] = v[: stop - start]
            else:
                self._keep(rows, start, stop)

    def flush(self, stop: int) -> None:
        """Complete the rows up to step ``stop``, send them to the sink, keep what the summary needs."""
        start = self.flushed
        if stop <= start:
            return
        a, b = start - self.base, stop - self.base
        if self.derived:
            for tr in self.worlds:
                derive_columns(tr, self.qidx, a, b)
        rows = self.buf.rows(a, b)
        if self.sink is not None:
            self.sink(rows, start)
        if not self.keep_rows:
            self._keep(rows, start, stop)
            self.buf.t[:] = np.nan  # the buffer starts again at step `stop`
            self.base = stop
        self.flushed = stop

    def _keep(self, rows: Trajectory, start: int, stop: int) -> None:
        self.keeper.keep(rows, start, stop)  # type: ignore[union-attr]

    def episode(
        self,
        w: int,
        cfg: EpisodeConfig,
        arena: ArenaSpec,
        done: int,
        wall: float,
        warnings: dict[str, int],
        *,
        stopped: bool = False,
    ) -> Episode:
        """World w's episode of its first ``done`` steps (``stopped``: it ended there by its ``until`` rule)."""
        if self.keep_rows:
            return finish_episode(cfg, arena, self.worlds[w].head(done), done, wall, warnings, stopped=stopped)
        self.buf = self.worlds[0] = Trajectory.empty(0, self.buf.qpos.shape[1])  # the chunk buffer is done with
        self.cols = {}
        keeper = self.keeper
        assert keeper is not None
        qpos_rows = getattr(self.sink, "qpos_rows", None)  # replays wedged periods' contacts (PartWriter)
        return finish_episode(
            cfg,
            arena,
            keeper.record(done),
            done,
            wall,
            warnings,
            qpos_rows=qpos_rows,
            picture=keeper.picture(done),
            stride=self.stride,
            stopped=stopped,
        )


@functools.lru_cache(maxsize=64)
def _constant(value: float, shape: tuple[int, ...]) -> np.ndarray:
    """A read-only array of ``shape`` holding ``value`` everywhere, in no memory (shared: nobody writes it)."""
    return np.broadcast_to(value, shape)


def finish_episode(
    cfg: EpisodeConfig,
    arena: ArenaSpec,
    rows: Trajectory | Record,
    done: int,
    wall: float,
    warnings: dict[str, int],
    *,
    qpos_rows: Callable[[np.ndarray], np.ndarray] | None = None,
    picture: Trajectory | None = None,
    stride: int = 1,
    stopped: bool = False,
) -> Episode:
    """The episode of a run's first ``done`` steps, for every engine: its summary (of ``rows``: the whole
    trajectory, or a streamed run's :class:`~neurowalk.sim.summarize.Record`), ``completed`` and ``steps_requested``.

    ``picture``: the rows the episode keeps when they are not ``rows`` (a streamed run's every ``stride``-th row).
    ``qpos_rows``: replays a streamed run's wedged periods (:func:`~neurowalk.sim.summarize.summarize`).
    ``stopped``: the run ended after ``done`` steps by its ``until`` rule (``EpisodeConfig.until``): it is complete,
    and ``stopped_by`` names the rule.
    """
    with profiling.part("summary"):  # the summary of the steps done
        summary = summarize(cfg, arena, rows, wall, warnings, qpos_rows=qpos_rows, steps=done) if done else {}
    summary = summary or {"steps": 0}
    summary["completed"] = done == cfg.steps or stopped
    summary["steps_requested"] = cfg.steps
    if stopped:
        summary["stopped_by"] = cfg.until
    kept = picture if picture is not None else rows
    assert isinstance(kept, Trajectory)
    return Episode(cfg, arena, kept, summary, row_stride=stride)


def in_region(x: Any, y: Any, region: tuple[Any, ...]) -> Any:
    """The trunk centre (x, y; m: ``qpos[0:2]``, the pose :func:`~neurowalk.sim.trajectory.poses_from_qpos` reads) is
    in ``region`` (x0, x1, y0, y1; m, edges included, as :func:`neurowalk.metrics.escaped` decides): a bool for
    numbers, a bool array for arrays of them (element by element; the bounds may be arrays too, one region each).
    Where a run with ``until="escaped"`` stops."""
    x0, x1, y0, y1 = region
    return (x0 <= x) & (x <= x1) & (y0 <= y) & (y <= y1)


def derive_columns(tr: Trajectory, qidx: np.ndarray | None, a: int, b: int) -> Trajectory:
    """Fill the derived columns (pose, joint angles, up_z) of rows [a, b) of ``tr`` from qpos; return ``tr``.

    ``qidx``: the 19 joints' places in ``qpos[7:]``, or None for a body without them (joint angles NaN).
    """
    q = tr.qpos[a:b]
    tr.pose[a:b] = poses_from_qpos(q)
    tr.joint_angles[a:b] = q[:, 7:][:, qidx] if qidx is not None else np.nan
    tr.up_z[a:b] = up_z_from_qpos(q)
    return tr
