"""The one control loop: observe → controller → joint targets → physics, at ``control_hz``.

.. code-block:: text

    body.reset(rng); controller.reset(rng)
    for each control step:
        obs = body.observe()              # copies; sensor noise from the run's Generator
        targets = controller.act(obs)     # 19 joint targets (rad)
        body.apply(targets); body.advance()   # n_substeps physics steps
        record

Every random draw comes from Generators spawned from one seed (``SeedSequence(seed).spawn``), so
the same seed gives the same trajectory, bit for bit. A long run streams its rows to a sink in chunks
and, with ``keep_rows=False``, keeps in memory only one chunk and the columns its summary needs.

The config, the episode and :func:`build` live in :mod:`neurowalk.sim.config`, the summary in
:mod:`neurowalk.sim.summary`; they are re-exported here.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Iterable
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from neurowalk.body.registry import body_info
from neurowalk.controller import Controller
from neurowalk.sim.checkpoint import Checkpoint, advance_keeping_previous, capture, restore
from neurowalk.sim.config import (
    BODIES,
    MAX_STEPS,
    Episode,
    EpisodeConfig,
    RunInterruptedError,
    build,
    progress_bar,
    seeds,
)
from neurowalk.sim.summary import PICTURE_ROWS, RecordKeeper, summarize
from neurowalk.sim.surrogate_episode import run_surrogate_episode
from neurowalk.sim.trajectory import Trajectory, poses_from_qpos, up_z_from_qpos

__all__ = [
    "BODIES",
    "MAX_STEPS",
    "PICTURE_ROWS",
    "Episode",
    "EpisodeConfig",
    "Resume",
    "RunInterruptedError",
    "build",
    "run_episode",
    "seeds",
    "summarize",
]


@dataclass(frozen=True)
class Resume:
    """Where a stopped physics run goes on: its checkpoint (the step and the whole state), the rows before it.

    ``head``: the rows before ``step``, as one trajectory or as (start, rows) pieces in step order (e.g. a
    :class:`~neurowalk.sim.trajectory.PartWriter`'s parts, read one at a time).
    """

    checkpoint: Checkpoint
    head: Trajectory | Iterable[tuple[int, Trajectory]]


def run_episode(
    cfg: EpisodeConfig,
    *,
    progress: bool = False,
    sink: Any = None,
    chunk: int = 10_000,
    keep_rows: bool = True,
    pad_boxes: int | None = None,
    checkpoint: Any = None,
    resume: Resume | None = None,
) -> Episode:
    """Run one episode and summarise it.

    Args:
        cfg: the run.
        progress: show a progress bar (rate, time left).
        sink: if given, called as ``sink(rows, start)`` after every ``chunk`` steps and at the end, ``rows``
            a :class:`Trajectory` of the steps ``start, start + 1, ...`` (valid during the call only), so that a
            long run can write its rows as it goes. A sink with a ``qpos_rows(rows)`` method (as
            :class:`~neurowalk.sim.trajectory.PartWriter`) lets a streamed run replay the obstacle contacts of
            its wedged periods.
        chunk: rows per sink call.
        keep_rows: keep every row in memory as ``Episode.trajectory``. False (with a ``sink``, every body):
            memory is bounded by ``chunk`` and the summary's columns (:class:`~neurowalk.sim.summary.Record`,
            41 bytes a step); ``Episode.trajectory`` holds every ``Episode.row_stride``-th row (at most
            :data:`PICTURE_ROWS`), for a picture.
        pad_boxes: run AMOSII on the model with that many obstacle slots, as :mod:`neurowalk.sim.batch` does.
        checkpoint: physics only: called as ``checkpoint(ckpt)`` after each ``chunk`` steps' sink call, ``ckpt`` a
            :class:`~neurowalk.sim.checkpoint.Checkpoint` of the whole body and controller (MuJoCo state, noise
            generators, networks) as arrays and JSON.
        resume: physics only: go on from such a checkpoint (:class:`Resume`); the continuation is bit for bit
            the run that was not stopped.

    Raises:
        RunInterruptedError: on KeyboardInterrupt; it carries the episode of the completed steps (the sink
            has received all of them).
    """
    if chunk < 1:
        raise ValueError(f"chunk must be at least 1 row, got {chunk}")
    if not keep_rows and sink is None:
        raise ValueError("keep_rows=False needs a sink: the rows would be lost")
    if not body_info(cfg.body).physics:  # surrogate, surrogate-wheeled: the planar bodies' compiled loop
        return run_surrogate_episode(
            cfg, progress=progress, sink=sink, chunk=chunk, keep_rows=keep_rows, picture_rows=PICTURE_ROWS
        )
    if cfg.engine == "warp":
        return _run_warp(cfg, progress, sink, chunk, resume)
    arena, body, ctrl = build(cfg, pad_boxes=pad_boxes if cfg.body == "amosii" else None)
    body_rng, ctrl_rng, _ = seeds(cfg)
    body.reset(body_rng)
    ctrl.reset(ctrl_rng)
    start = 0
    if resume is not None:
        start = resume.checkpoint.step
        restore(resume.checkpoint, {"body": body, "controller": ctrl})
    rec = _Recorder(cfg.steps, body, sink, chunk, keep_rows, start)
    if resume is not None:
        rec.restore(resume.head)
    bar = progress_bar(cfg.steps, progress)
    if bar is not None:
        bar.update(start)
    t0 = time.perf_counter()
    done = start
    try:
        done = _loop(cfg, body, ctrl, rec, bar, start, checkpoint)
    except KeyboardInterrupt:
        done = rec.done()
    except OSError:
        raise  # a write that failed: writing again would fail too
    except Exception:
        with contextlib.suppress(Exception):  # a failure in the loop: hand the completed rows on, then report it
            rec.flush(rec.done())
        raise
    wall = time.perf_counter() - t0
    if bar is not None:
        bar.close()
    rec.flush(done)
    ep = rec.episode(cfg, arena, body, done, wall)
    if start and done > start and wall > 0:  # this invocation's part of a resumed run: its wall time, its rate
        ep.summary["resumed_at_step"] = start
        ep.summary["real_time_factor"] = (done - start) / cfg.control_hz / wall
    if done < cfg.steps:
        raise RunInterruptedError(ep)
    return ep


def _run_warp(cfg: EpisodeConfig, progress: bool, sink: Any, chunk: int, resume: Resume | None) -> Episode:
    """One run on MuJoCo Warp (one world; :mod:`neurowalk.sim.warp_engine`); its rows go to ``sink`` at the end."""
    from neurowalk.sim.warp_engine import run_warp

    if resume is not None:
        raise ValueError("a run on engine 'warp' cannot be resumed (no checkpoints); run it again")
    ep = run_warp([cfg], progress=progress)[0]
    done = len(ep.trajectory)
    if sink is not None:
        for start in range(0, done, chunk):
            sink(ep.trajectory.rows(start, min(start + chunk, done)), start)
    if done < cfg.steps:
        raise RunInterruptedError(ep)
    return ep


def _loop(
    cfg: EpisodeConfig, body: Any, ctrl: Controller, rec: _Recorder, bar: Any, start: int, checkpoint: Any
) -> int:
    """The control loop proper, from step ``start``; returns the number of completed steps."""
    d = body.data
    has_weights = hasattr(ctrl, "b")
    buf, base = rec.buf, rec.base
    steering = body.action == "steering"  # the body takes the steering pair (e.g. wheels), not joint targets
    every = rec.chunk if checkpoint is not None else 0
    previous = None
    for k in range(start, cfg.steps):
        obs = body.observe()
        targets = ctrl.act(obs)
        body.apply(ctrl.steering if steering else targets)
        if every and (k + 1) % every == 0:
            previous = advance_keeping_previous(body)  # what a checkpoint needs to continue bit for bit
        else:
            body.advance()
        i = k - base
        buf.inputs[i] = ctrl.inputs
        buf.outputs[i] = ctrl.steering
        if has_weights:
            buf.b[i] = ctrl.b  # type: ignore[attr-defined]
            buf.q[i] = ctrl.q  # type: ignore[attr-defined]
        buf.targets[i] = targets
        buf.us_distance[i] = obs.us_distance
        buf.foot_contact[i] = obs.foot_contact
        buf.qpos[i] = d.qpos
        buf.t[i] = d.time  # last: a row with a time is complete
        if bar is not None and k % 100 == 99:
            bar.update(100)
        if (k + 1) % rec.chunk == 0:
            rec.flush(k + 1)
            buf, base = rec.buf, rec.base
            if checkpoint is not None and k + 1 < cfg.steps:
                checkpoint(capture(k + 1, {"body": body, "controller": ctrl}, previous))
    return cfg.steps


class _Recorder:
    """Where the loop writes its rows: the whole run in memory, or one chunk at a time (``keep_rows=False``).

    ``buf`` holds the steps from ``base`` on; :meth:`flush` completes the rows written since the last flush
    (derived columns), hands them to the sink, copies the summary's columns and the picture's rows out of a
    chunk buffer and starts the buffer again.
    """

    def __init__(self, steps: int, body: Any, sink: Any, chunk: int, keep_rows: bool, start: int) -> None:
        qidx = body._qidx - 7 if body.action == "targets" else None  # the 19 joints in qpos[7:] (legged body)
        self.sink, self.keep_rows, self.qidx = sink, keep_rows, qidx
        self.chunk = chunk if sink is not None or not keep_rows else steps
        self.flushed = start
        nq = body.model.nq
        self.buf = Trajectory.empty(steps if keep_rows else self.chunk, nq)
        self.base = 0 if keep_rows else start
        self.keeper = None if keep_rows else RecordKeeper(steps, nq, PICTURE_ROWS)
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
                for f in fields(Trajectory):
                    getattr(self.buf, f.name)[start:stop] = getattr(rows, f.name)[: stop - start]
            else:
                self._keep(rows, start, stop)

    def flush(self, stop: int) -> None:
        """Complete the rows up to step ``stop``, send them to the sink, keep what the summary needs."""
        start = self.flushed
        if stop <= start:
            return
        a, b = start - self.base, stop - self.base
        _derive(self.buf, self.qidx, a, b)
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

    def episode(self, cfg: EpisodeConfig, arena: Any, body: Any, done: int, wall: float) -> Episode:
        """The episode of the first ``done`` steps."""
        run_cfg = cfg if done == cfg.steps else replace(cfg, steps=max(done, 1))
        if self.keep_rows:
            tr = self.buf.head(done)
            summary = summarize(run_cfg, arena, tr, wall, body.warnings()) if done else {"steps": 0}
        else:
            self.buf = Trajectory.empty(0, self.buf.qpos.shape[1])  # the chunk buffer is done with
            cut = self.keeper.record(done)  # type: ignore[union-attr]
            qpos_rows = getattr(self.sink, "qpos_rows", None)  # replays wedged periods' contacts (PartWriter)
            summary = summarize(run_cfg, arena, cut, wall, body.warnings(), qpos_rows=qpos_rows) if done else {}
            tr = self.keeper.picture(done)  # type: ignore[union-attr]
        summary = summary or {"steps": 0}
        summary["completed"] = done == cfg.steps
        summary["steps_requested"] = cfg.steps
        return Episode(cfg, arena, tr, summary, row_stride=self.stride)


def _derive(tr: Trajectory, qidx: np.ndarray | None, a: int, b: int) -> Trajectory:
    """Fill the derived columns (pose, joint angles, up_z) of rows [a, b) of ``tr`` from qpos; return ``tr``.

    ``qidx``: the 19 joints' places in ``qpos[7:]``, or None for a body without them (joint angles NaN).
    """
    q = tr.qpos[a:b]
    tr.pose[a:b] = poses_from_qpos(q)
    tr.joint_angles[a:b] = q[:, 7:][:, qidx] if qidx is not None else np.nan
    tr.up_z[a:b] = up_z_from_qpos(q)
    return tr
