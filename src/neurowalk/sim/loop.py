"""The one loop: n worlds of any body, their controllers, one control step after another; resumable.

.. code-block:: text

    worlds.reset(body rngs); controllers.reset(controller rngs)        # each run's seeds()
    for each control step:
        dist, foot = worlds.sense()                                   # the body senses itself; noise of each seed
        targets = controllers.step(dist, worlds.observation)          # one compiled call, or each one's act()
        worlds.apply(targets or the steering pairs); worlds.advance()
        record; stop worlds in their exit region (until="escaped"); progress; checkpoint

Every engine runs this loop: the CPU loop (one world, :class:`~neurowalk.body.world.OneWorld`), the lock-step
worlds of ``mujoco.batch`` and MuJoCo Warp (:class:`~neurowalk.body.amosii_worlds.AmosIIWorlds`), and the planar
surrogate, whose body and controller step together in compiled chunks of control steps
(:class:`~neurowalk.body.world.CompiledWorld`: the loop hands it ``Streaming.chunk`` steps a call). Every random draw
comes from Generators spawned from each run's seed (``SeedSequence(seed).spawn``), so the same seed gives the same
trajectory, bit for bit, in one world or many. One world's rows may stream to a sink in chunks and that run writes
checkpoints from which a stopped run goes on bit for bit (:class:`~neurowalk.sim.engine_interface.Streaming`).
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import cast

import numpy as np

from neurowalk import profiling
from neurowalk.arenas import ArenaSpec
from neurowalk.body.world import CompiledWorld, OneWorld, PlanarWorld, World, is_compiled
from neurowalk.progress import Progress
from neurowalk.sim.batch_control import BatchControllers
from neurowalk.sim.checkpoint import capture, restore
from neurowalk.sim.config import Episode, EpisodeConfig, progress_bar, seeds
from neurowalk.sim.engine_interface import Streaming
from neurowalk.sim.recorder import Recorder, in_region
from neurowalk.sim.trajectory import STATE

__all__ = ["TIMING", "Run", "run_worlds"]

#: The parts of a control step the loop times (s): ``physics`` (apply and advance) and ``control``, the host's
#: part, which is ``sense`` (sensor model and noise) + ``controllers`` + ``record``.
TIMING = ("physics", "control", "sense", "controllers", "record")


@dataclass
class Run:
    """What :func:`run_worlds` gives: one episode per world, the control steps run, and whether the run was stopped
    part-way (Ctrl-C, a stop request) before every world was done."""

    episodes: list[Episode]
    done: int
    interrupted: bool


def run_worlds(
    configs: Sequence[EpisodeConfig],
    arenas: Sequence[ArenaSpec],
    worlds: World | CompiledWorld,
    controllers: BatchControllers,
    stream: Streaming | None = None,
    *,
    progress: bool = False,
    label: str = "episode",
    timing: dict[str, float] | None = None,
) -> Run:
    """Reset ``worlds`` (one per config) and their controllers from each config's seeds and run them for the
    configs' ``steps`` (the same for all), from ``stream.resume`` if given (one world).

    Each episode's ``wall_time_s`` is the run's wall time divided by the number of worlds. ``timing``: seconds are
    added to its :data:`TIMING` keys. Stopped part-way (KeyboardInterrupt) it returns the episodes of the completed
    steps, each with ``summary["completed"]`` false (:attr:`Run.interrupted`). A
    failure in the loop hands the completed rows to the sink, then is raised.
    """
    stream = stream or Streaming()
    n, steps = worlds.n, configs[0].steps
    rngs = [seeds(c) for c in configs]
    worlds.reset([body for body, _, _ in rngs])
    controllers.reset([ctrl for _, ctrl, _ in rngs])
    roots = _roots(worlds, controllers) if stream.resume is not None or stream.checkpoint is not None else None
    start = 0
    if stream.resume is not None:
        start = stream.resume.checkpoint.step
        assert roots is not None
        restore(stream.resume.checkpoint, roots)
    rec = Recorder(steps, worlds, stream, start, controllers.recorded)
    if stream.resume is not None:
        rec.restore(stream.resume.head)
    bar = progress_bar(steps * n, progress, label, initial=start * n)
    regions = [a.exit_region if c.until == "escaped" else None for c, a in zip(configs, arenas, strict=True)]
    stopped_at = np.full(n, -1)
    t0 = time.perf_counter()
    done, interrupted = start, False
    try:
        if is_compiled(worlds) and any(part is not None for part in controllers.compiled_parts(0)):
            done = _chunks(worlds, controllers, rec, start, steps, bar, stream, configs[0].control_hz)
        else:
            done = _steps(cast(World, worlds), controllers, rec, start, steps, regions, stopped_at, bar, stream, roots,
                          timing)  # fmt: skip
    except KeyboardInterrupt:
        done, interrupted = rec.done(), True
    except OSError:
        raise  # a write that failed: writing again would fail too
    except Exception:
        with contextlib.suppress(Exception):  # a failure in the loop: hand the completed rows on, then report it
            rec.flush(rec.done())
        raise
    wall = (time.perf_counter() - t0) / n
    if bar is not None:
        bar.close()
    rec.flush(done)
    episodes = []
    for w, (cfg, arena) in enumerate(zip(configs, arenas, strict=True)):
        stopped = bool(stopped_at[w] >= 0)
        ep = rec.episode(w, cfg, arena, int(stopped_at[w]) if stopped else done, wall, worlds.warnings(w),
                         stopped=stopped)  # fmt: skip
        if start and done > start and wall > 0:  # this invocation's part of a resumed run: its wall time, its rate
            ep.summary["resumed_at_step"] = start
            ep.summary["real_time_factor"] = (done - start) / cfg.control_hz / wall
        episodes.append(ep)
    return Run(episodes, done, interrupted or (done < steps and not (stopped_at >= 0).all()))


def _roots(worlds: World | CompiledWorld, controllers: BatchControllers) -> dict[str, object]:
    """What a checkpoint holds: the one world's body and its controller."""
    if not isinstance(worlds, OneWorld) or controllers.compiled:
        raise ValueError("checkpoints are of one world whose controller steps by act()")
    return {"body": worlds.body, "controller": controllers.controllers[0]}


def _chunks(
    worlds: CompiledWorld,
    ctl: BatchControllers,
    rec: Recorder,
    start: int,
    steps: int,
    bar: Progress | None,
    stream: Streaming,
    control_hz: float,
) -> int:
    """The control steps from ``start`` of a world compiled with its controller, ``stream.chunk`` steps a compiled
    call; returns the steps completed. ``stream.stop()`` (asked after each call) stops the run as a
    KeyboardInterrupt would, before that call's rows count (they get no time)."""
    network, steer = ctl.compiled_parts(0)
    if network is None and steer is None:
        raise ValueError("a compiled world runs the compiled controllers only (plastic, static, braitenberg, fixed)")
    t_col = rec.cols["t"]
    for k0 in range(start, steps, stream.chunk):
        k1 = min(steps, k0 + stream.chunk)
        worlds.rollout(k0, k1, rec.cols, rec.base, network, steer)
        if stream.stop is not None and stream.stop():
            raise KeyboardInterrupt
        t_col[:, k0 - rec.base : k1 - rec.base] = np.arange(k0 + 1, k1 + 1) / control_hz  # last: the rows complete
        if bar is not None:
            bar.update((k1 - k0) * worlds.n)
        if k1 % rec.chunk == 0:
            rec.flush(k1)
    return steps


def _steps(
    worlds: World,
    ctl: BatchControllers,
    rec: Recorder,
    start: int,
    steps: int,
    regions: list[tuple[float, float, float, float] | None],
    stopped_at: np.ndarray,
    bar: Progress | None,
    stream: Streaming,
    roots: dict[str, object] | None,
    timing: dict[str, float] | None,
) -> int:
    """The control steps from ``start``; returns the steps completed: fewer than ``steps`` where every world
    stopped by its ``until`` rule (world i's trunk centre, ``qpos[i, 0:2]``, entered its exit region: step
    ``stopped_at[i]``) or ``stream.stop()`` (asked every 100 steps) asked to stop (as a KeyboardInterrupt)."""
    n, cols, nq = worlds.n, rec.cols, worlds.nq
    inputs, outputs, b, q, targets_c, us, foot_c, qpos_c, t_c = (cols[k] for k in rec.buf.RECORDED)
    joints = "targets" in worlds.columns  # (a planar world: no joints, no feet, no positions but its pose)
    state = [(rec.state[STATE + k], a) for k, a in ctl.state.items()]  # the controllers' declared state
    planar = None if nq else cast(PlanarWorld, worlds)  # a world without positions gives its pose
    steering = worlds.action == "steering"  # the body takes the steering pair (e.g. wheels), not joint targets
    stopping = nq > 0 and any(r is not None for r in regions)
    bounds = tuple(np.array([r if r is not None else (np.nan,) * 4 for r in regions]).T)  # NaN: never stops
    every = rec.chunk if stream.checkpoint is not None else 0
    keep = worlds.advance_keeping_previous if every and isinstance(worlds, OneWorld) else None
    previous = None
    clock = time.perf_counter
    parts = dict.fromkeys(TIMING, 0.0)
    done, base = start, rec.base
    try:
        for k in range(start, steps):
            t0 = clock()
            dist, foot = worlds.sense()
            t1 = clock()
            targets = ctl.step(dist, worlds.observation)
            t2 = clock()
            worlds.apply(ctl.outputs if steering else targets)
            if keep is not None and (k + 1) % every == 0:
                previous = keep()  # what a checkpoint needs to continue bit for bit
            else:
                worlds.advance()
            t3 = clock()
            i = k - base
            inputs[:, i], outputs[:, i], b[:, i], q[:, i], us[:, i] = ctl.inputs, ctl.outputs, ctl.b, ctl.q, dist
            if joints:
                targets_c[:, i], foot_c[:, i] = targets, foot
            for col, values in state:
                col[:, i] = values
            qpos = worlds.qpos
            if planar is None:
                qpos_c[:, i] = qpos
            else:
                cols["pose"][:, i] = planar.pose
            t_c[:, i] = worlds.time  # last: a row with a time is complete
            done = k + 1
            t4 = clock()
            parts["physics"] += t3 - t2
            parts["sense"] += t1 - t0
            parts["controllers"] += t2 - t1
            parts["record"] += t4 - t3
            if k % 100 == 99:
                if bar is not None:
                    bar.update(100 * n)
                if stream.stop is not None and stream.stop():
                    raise KeyboardInterrupt
            if stopping:
                inside = in_region(qpos[:, 0], qpos[:, 1], bounds) & (stopped_at < 0)
                if inside.any():
                    stopped_at[inside] = done
                    if (stopped_at >= 0).all():
                        return done
            if done % rec.chunk == 0:
                rec.flush(done)
                base = rec.base
                if stream.checkpoint is not None and done < steps:
                    stream.checkpoint(capture(done, cast(dict[str, object], roots), previous))
        return steps
    finally:  # the profile's physics (its steps) and control parts, also of a run stopped part-way
        parts["control"] = parts["sense"] + parts["controllers"] + parts["record"]
        profiling.add("physics", parts["physics"], (done - start) * n * worlds.n_substeps)
        profiling.add("control", parts["control"])
        if timing is not None:
            for key, value in parts.items():
                timing[key] += value
