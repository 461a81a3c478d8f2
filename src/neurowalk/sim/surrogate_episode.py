"""An episode on the planar surrogate body: the same config, seeds, trajectory and summary as physics.

The sensory network runs inside the surrogate's compiled loop (the locomotion network is skipped: the
surrogate needs only the steering). Rows that only physics has (joint targets and angles, foot
contacts, qpos) are NaN or empty; ``up_z`` is 1.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from neurowalk.body.surrogate import Surrogate, SurrogateRun, empty_run
from neurowalk.controller import NeuralController
from neurowalk.sim.config import Episode, EpisodeConfig, RunInterruptedError, build, progress_bar, seeds
from neurowalk.sim.engine_interface import EngineOptions, OneWorldPerCall, Streaming
from neurowalk.sim.recorder import finish_episode
from neurowalk.sim.summarize import PICTURE_ROWS, RecordKeeper
from neurowalk.sim.trajectory import Trajectory


def trajectory_of(run: SurrogateRun, control_hz: float, fixed: bool, first: int = 0) -> Trajectory:
    """The :class:`Trajectory` view of a surrogate run's arrays (shared, not copied); row 0 is step ``first``."""
    steps = len(run.pose)
    t = np.arange(first + 1, first + steps + 1) / control_hz
    b, q = run.weights[:, :2], run.weights[:, 2:]
    if fixed:
        b, q = np.full((steps, 2), np.nan), np.full((steps, 2), np.nan)
    nan = np.broadcast_to(np.nan, (steps, 19))  # read-only views: no memory for what a planar body lacks
    return Trajectory(
        t=t,
        pose=run.pose,
        inputs=run.inputs,
        outputs=run.outputs,
        b=b,
        q=q,
        targets=nan,
        joint_angles=nan,
        us_distance=run.us,
        foot_contact=np.broadcast_to(np.nan, (steps, 6)),
        up_z=np.broadcast_to(1.0, (steps,)),
        qpos=np.empty((steps, 0)),
    )


def run_surrogate_episode(
    cfg: EpisodeConfig,
    *,
    progress: bool = False,
    sink: Callable[[Trajectory, int], object] | None = None,
    chunk: int = 10_000,
    keep_rows: bool = True,
    picture_rows: int = PICTURE_ROWS,
    stop: Callable[[], bool] | None = None,
) -> Episode:
    """:func:`neurowalk.sim.episode.run_episode` for the planar bodies (same arguments and errors).

    ``keep_rows=False`` (with a ``sink``): the run goes in chunks of ``chunk`` rows through one chunk's arrays,
    keeping the summary's columns and a picture's rows (:class:`~neurowalk.sim.summarize.RecordKeeper`), so memory
    does not grow with the run's rows; ``Episode.trajectory`` holds every ``row_stride``-th row (at most
    ``picture_rows``).
    """
    arena, body, ctrl = build(cfg)
    assert isinstance(body, Surrogate)
    body_rng, ctrl_rng, _ = seeds(cfg)
    ctrl.reset(ctrl_rng)
    fixed = not isinstance(ctrl, NeuralController)
    state = params = None
    if isinstance(ctrl, NeuralController):
        state, params = ctrl.sensory.state, ctrl.sensory.packed_params
    run = empty_run(chunk if not keep_rows else cfg.steps)
    keeper = None if keep_rows else RecordKeeper(cfg.steps, 0, picture_rows)
    bar = progress_bar(cfg.steps, progress)
    last = [0]

    def on_chunk(end: int) -> None:
        if stop is not None and stop():  # before its rows are handed on: this chunk does not count
            raise KeyboardInterrupt
        start = last[0]
        if keeper is not None:
            rows = trajectory_of(run, cfg.control_hz, fixed, start).head(end - start)
            if sink is not None:
                sink(rows, start)
            keeper.keep(rows, start, end)
        elif sink is not None:  # (no views are made when nobody takes them)
            sink(trajectory_of(run, cfg.control_hz, fixed).rows(start, end), start)
        last[0] = end
        if bar is not None:
            bar.update(end - start)

    t0 = time.perf_counter()
    body.run(
        cfg.steps,
        body_rng,
        state,
        params,
        steer=cfg.steer,
        chunk=chunk,
        on_chunk=on_chunk,
        out=run,
        stream=keeper is not None,
    )
    wall = time.perf_counter() - t0
    if bar is not None:
        bar.close()
    done = run.done  # the rows handed to the sink: a chunk whose hand-over was interrupted does not count
    if keeper is None:
        ep = finish_episode(cfg, arena, trajectory_of(run, cfg.control_hz, fixed).head(done), done, wall, {})
    else:
        ep = finish_episode(
            cfg, arena, keeper.record(done), done, wall, {}, picture=keeper.picture(done), stride=keeper.stride
        )
    summary = ep.summary
    summary["surrogate_contacts"] = run.contacts
    if done < cfg.steps:
        raise RunInterruptedError(ep)
    return ep


class SurrogateLoop(OneWorldPerCall):
    """The planar bodies' engine: the surrogate's compiled loop, runs one after another; streams its rows."""

    name = "surrogate"

    def run_one(self, cfg: EpisodeConfig, options: EngineOptions, stream: Streaming) -> Episode:
        """One run (:func:`run_surrogate_episode`); a planar run is not resumed (it reruns in seconds)."""
        if stream.resume is not None or stream.checkpoint is not None:
            raise ValueError(f"a run of body {cfg.body!r} cannot be resumed (no checkpoints); run it again")
        return run_surrogate_episode(
            cfg,
            progress=options.progress,
            sink=stream.sink,
            chunk=stream.chunk,
            keep_rows=stream.keep_rows,
            picture_rows=stream.picture_rows,
            stop=stream.stop,
        )
