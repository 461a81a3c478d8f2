"""The CPU loop: one MuJoCo world (or a body of any kind), one control step after another; resumable.

.. code-block:: text

    body.reset(rng); controller.reset(rng)
    for each control step:
        obs = body.observe()              # copies; sensor noise from the run's Generator
        targets = controller.act(obs)     # 19 joint targets (rad)
        body.apply(targets); body.advance()   # n_substeps physics steps
        record

Every random draw comes from Generators spawned from one seed (``SeedSequence(seed).spawn``), so the same seed
gives the same trajectory, bit for bit. A long run streams its rows to a sink in chunks (:class:`Streaming`) and,
with ``keep_rows=False``, keeps in memory only one chunk and the columns its summary needs; it writes checkpoints
from which a stopped run goes on bit for bit.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable
from typing import Any

from neurowalk import profiling
from neurowalk.controller import Controller
from neurowalk.progress import Progress
from neurowalk.sim.checkpoint import Checkpoint, advance_keeping_previous, capture, restore
from neurowalk.sim.config import Episode, EpisodeConfig, RunInterruptedError, build, progress_bar, seeds
from neurowalk.sim.engine_interface import EngineOptions, OneWorldPerCall, Streaming
from neurowalk.sim.recorder import Recorder, in_region

__all__ = ["CpuLoop"]


class CpuLoop(OneWorldPerCall):
    """The CPU loop (engine ``mujoco``): one world per run, runs one after another; resumable, streams its rows."""

    name = "mujoco"
    resumable = True

    def run_one(self, cfg: EpisodeConfig, options: EngineOptions, stream: Streaming) -> Episode:
        """One run, its rows streamed to ``stream.sink`` as it goes, from ``stream.resume`` if given.

        Raises:
            RunInterruptedError: on KeyboardInterrupt; it carries the episode of the completed steps (the sink has
                received all of them).
        """
        arena, body, ctrl = build(cfg, pad_boxes=options.pad_boxes)
        body_rng, ctrl_rng, _ = seeds(cfg)
        body.reset(body_rng)
        ctrl.reset(ctrl_rng)
        start = 0
        if stream.resume is not None:
            start = stream.resume.checkpoint.step
            restore(stream.resume.checkpoint, {"body": body, "controller": ctrl})
        rec = Recorder(cfg.steps, body, stream, start)
        if stream.resume is not None:
            rec.restore(stream.resume.head)
        bar = progress_bar(cfg.steps, options.progress, initial=start)
        t0 = time.perf_counter()
        done = start
        stop_region = arena.exit_region if cfg.until == "escaped" else None
        stopped = False
        try:
            done = _loop(cfg, body, ctrl, rec, bar, start, stream.checkpoint, stop_region, stream.stop)
            stopped = done < cfg.steps
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
        ep = rec.episode(cfg, arena, body, done, wall, stopped=stopped)
        if start and done > start and wall > 0:  # this invocation's part of a resumed run: its wall time, its rate
            ep.summary["resumed_at_step"] = start
            ep.summary["real_time_factor"] = (done - start) / cfg.control_hz / wall
        if done < cfg.steps and not stopped:
            raise RunInterruptedError(ep)
        return ep


def _loop(
    cfg: EpisodeConfig,
    body: Any,
    ctrl: Controller,
    rec: Recorder,
    bar: Progress | None,
    start: int,
    checkpoint: Callable[[Checkpoint], object] | None,
    stop_region: tuple[float, float, float, float] | None = None,
    stop: Callable[[], bool] | None = None,
) -> int:
    """The control loop proper, from step ``start``; returns the number of completed steps (fewer than
    ``cfg.steps`` where the trunk centre, ``qpos[0:2]``, entered ``stop_region`` (x0, x1, y0, y1; m)).
    ``stop()`` True (asked every 100 steps) ends it as a KeyboardInterrupt would (:class:`Streaming`)."""
    d = body.data
    has_weights = hasattr(ctrl, "b")
    buf, base = rec.buf, rec.base
    steering = body.action == "steering"  # the body takes the steering pair (e.g. wheels), not joint targets
    every = rec.chunk if checkpoint is not None else 0
    previous = None
    clock = time.perf_counter
    t_start, physics, done = clock(), 0.0, start
    try:
        for k in range(start, cfg.steps):
            obs = body.observe()
            targets = ctrl.act(obs)
            body.apply(ctrl.steering if steering else targets)
            t = clock()
            if every and (k + 1) % every == 0:
                previous = advance_keeping_previous(body)  # what a checkpoint needs to continue bit for bit
            else:
                body.advance()
            physics += clock() - t
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
            done = k + 1
            if k % 100 == 99:
                if bar is not None:
                    bar.update(100)
                if stop is not None and stop():
                    raise KeyboardInterrupt
            if stop_region is not None and in_region(d.qpos[0], d.qpos[1], stop_region):
                return done
            if (k + 1) % rec.chunk == 0:
                rec.flush(k + 1)
                buf, base = rec.buf, rec.base
                if checkpoint is not None and k + 1 < cfg.steps:
                    checkpoint(capture(k + 1, {"body": body, "controller": ctrl}, previous))
        return cfg.steps
    finally:  # the profile's physics (its steps) and control parts, also of a run stopped part-way
        profiling.add("physics", physics, (done - start) * getattr(body, "n_substeps", 1))
        profiling.add("control", clock() - t_start - physics)
