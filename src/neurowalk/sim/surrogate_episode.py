"""An episode on the planar surrogate body: the same config, seeds, trajectory and summary as physics.

The sensory network runs inside the surrogate's compiled loop (the locomotion network is skipped: the
surrogate needs only the steering). Rows that only physics has (joint targets and angles, foot
contacts, qpos) are NaN or empty; ``up_z`` is 1.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import numpy as np

from neurowalk.body.surrogate import Surrogate, SurrogateRun, empty_run
from neurowalk.controller import NeuralController
from neurowalk.sim.config import Episode, EpisodeConfig, RunInterruptedError, build, progress_bar, seeds
from neurowalk.sim.summary import summarize
from neurowalk.sim.trajectory import Trajectory


def trajectory_of(run: SurrogateRun, control_hz: float, fixed: bool) -> Trajectory:
    """The :class:`Trajectory` view of a surrogate run's arrays (rows are shared, not copied)."""
    steps = len(run.pose)
    t = np.arange(1, steps + 1) / control_hz
    b, q = run.weights[:, :2], run.weights[:, 2:]
    if fixed:
        b, q = np.full((steps, 2), np.nan), np.full((steps, 2), np.nan)
    nan = np.broadcast_to(np.nan, (steps, 19))  # read-only views: no memory for what a planar body lacks
    return Trajectory(t=t, pose=run.pose, inputs=run.inputs, outputs=run.outputs, b=b, q=q, targets=nan,
                      joint_angles=nan, us_distance=run.us, foot_contact=np.broadcast_to(np.nan, (steps, 6)),
                      up_z=np.broadcast_to(1.0, (steps,)), qpos=np.empty((steps, 0)))  # fmt: skip


def run_surrogate_episode(cfg: EpisodeConfig, *, progress: bool = False, sink: Any = None,
                          chunk: int = 10_000) -> Episode:  # fmt: skip
    """:func:`neurowalk.sim.episode.run_episode` for ``body='surrogate'`` (same arguments and errors)."""
    arena, body, ctrl = build(cfg)
    assert isinstance(body, Surrogate)
    body_rng, ctrl_rng, _ = seeds(cfg)
    ctrl.reset(ctrl_rng)
    fixed = not isinstance(ctrl, NeuralController)
    state = params = None
    if not fixed:
        state, params = ctrl.sensory.state, ctrl.sensory.packed_params
    run = empty_run(cfg.steps)
    tr = trajectory_of(run, cfg.control_hz, fixed)
    bar = progress_bar(cfg.steps, progress)
    last = [0]

    def on_chunk(stop: int) -> None:
        if bar is not None:
            bar.update(stop - last[0])
        if sink is not None:
            sink(tr.rows(last[0], stop), last[0])
        last[0] = stop

    t0 = time.perf_counter()
    body.run(cfg.steps, body_rng, state, params, steer=cfg.steer, chunk=chunk, on_chunk=on_chunk, out=run)
    wall = time.perf_counter() - t0
    if bar is not None:
        bar.close()
    done = run.done
    tr = tr.head(done)
    run_cfg = cfg if done == cfg.steps else replace(cfg, steps=max(done, 1))
    summary = summarize(run_cfg, arena, tr, wall, {}) if done else {"steps": 0}
    summary["completed"] = done == cfg.steps
    summary["steps_requested"] = cfg.steps
    summary["surrogate_contacts"] = run.contacts
    ep = Episode(cfg, arena, tr, summary)
    if done < cfg.steps:
        raise RunInterruptedError(ep)
    return ep
