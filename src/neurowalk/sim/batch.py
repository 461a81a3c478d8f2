"""Many runs at once on ``mujoco.batch``: one padded AMOSII model per arena, all stepped together on threads.

.. code-block:: text

    models  = AmosII(arena_i, pad_boxes=max_boxes).model   # same sizes for all (body/obstacle_slots.py); one per
                                                           # distinct arena, shared by the worlds in it
    batch   = mujoco.batch.Batch(models[0], n, nthread); batch.set_models(models)
    reset:  stand keyframe at each arena's start pose; noise and controllers from each run's seeds()
    each control step (sim/lockstep.py): sense all copies, controllers in one compiled call,
        ctrl[:] = targets; batch.step(nstep=n_substeps)                     # on nthread threads

Copy i gives exactly (bit for bit) the trajectory of ``run_episode(configs[i])``: the padded model's physics
is the plain model's (see ``obstacle_slots``), the reset is AmosII.reset's, the noise draws come from the same
Generators in the same order, the controllers run the same kernels, and MuJoCo's batch is bit-identical to a
loop over one ``MjData`` per copy. tests/sim/test_batch.py checks it.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import mujoco.batch
import numpy as np

from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.body.amosii import AmosII
from neurowalk.body.common import place_at_start
from neurowalk.body.registry import make_body
from neurowalk.sim.config import Episode, EpisodeConfig, seeds
from neurowalk.sim.engine_interface import EngineOptions
from neurowalk.sim.lockstep import LockstepEngine, LockstepWorlds

__all__ = ["BatchPhysics", "MujocoBatch", "MujocoBatchWorlds", "run_batch"]


class BatchPhysics:
    """The physics of AMOSII's many worlds on one ``mujoco.batch.Batch``: the part of an
    :class:`~neurowalk.body.amosii_worlds.AmosIIWorlds` that a batch plugs in (its reset, apply, advance and warnings),
    mixed in before it (:class:`MujocoBatchWorlds`, the Gymnasium physics vector environment's copies)."""

    batch: mujoco.batch.Batch
    arenas: list[ArenaSpec]
    n: int
    n_substeps: int
    stand_key: int
    qpos: np.ndarray
    ctrl: np.ndarray
    sensordata: np.ndarray
    sim_time: np.ndarray
    xpos: np.ndarray | None
    xmat: np.ndarray | None

    def bind_batch(self, batch: mujoco.batch.Batch) -> None:
        """Step ``batch``: its positions, controls, sensor data, times and the bodies' places (a whole observation's
        pose) are the worlds'. Bound before the first call: a batch's outputs fill only after one."""
        self.batch = batch
        self.qpos, self.ctrl = batch.bind("qpos"), batch.bind("ctrl")
        self.sensordata, self.sim_time = batch.bind("sensordata"), batch.bind("time")
        self.xpos, self.xmat = batch.bind("xpos"), batch.bind("xmat")

    def reset_physics(self, ids: np.ndarray | None = None) -> None:
        """Every world (or worlds ``ids``: a Gymnasium copy's new episode): the stand keyframe at its arena's start
        pose, forward-computed, as AmosII.reset."""
        which = {} if ids is None else {"ids": ids}
        self.batch.reset(keyframe=self.stand_key, stage=mujoco.mjtStage.mjSTAGE_NONE, **which)
        for i in range(self.n) if ids is None else ids:
            place_at_start(self.qpos[i], self.arenas[i].start)
        self.batch.forward(**which)

    def apply(self, actions: np.ndarray) -> None:
        """Every world's joint targets (n, nu), rad."""
        self.ctrl[:] = actions

    def advance(self) -> None:
        """One control step of physics in every world (on the batch's threads)."""
        self.batch.step(nstep=self.n_substeps)

    def warnings(self, i: int) -> dict[str, int]:
        """MuJoCo warnings of world i so far, by name (empty when none)."""
        counts = self.batch.warning[i, :, 1]
        return {mujoco.mjtWarning(w).name: int(c) for w, c in enumerate(counts) if c}


class MujocoBatchWorlds(BatchPhysics, LockstepWorlds):
    """n runs of AMOSII (one per config) in one ``mujoco.batch.Batch``.

    Args:
        configs: the runs; same body (``amosii``), ``control_hz`` and ``steps``; arenas, seeds, controllers,
            noise and start weights may differ.
        nthread: physics threads (the calling thread is one of them).
        max_boxes: boxes the padded models have room for (default: the most boxes of any arena).
        persistent: keep one ``MjData`` per copy inside the batch (more memory; the same numbers).
        compiled: step the controllers in one compiled call (else each controller's ``act``).

    Attributes:
        arenas: the arena of each run. models: the padded model of each run (``model``: the first).
        batch: the ``mujoco.batch.Batch``. n_substeps: physics steps per control step.
        timing: seconds spent so far in ``physics`` (batch.step) and in ``control`` (sensing, controllers,
            recording).
    """

    def __init__(
        self,
        configs: Sequence[EpisodeConfig],
        *,
        nthread: int = 2,
        max_boxes: int | None = None,
        persistent: bool = False,
        compiled: bool = True,
    ) -> None:
        configs = list(configs)
        MujocoBatch().check(configs, EngineOptions(threads=nthread))
        arenas = [make_arena(c.arena, rng=seeds(c)[2], **c.arena_opts) for c in configs]  # as build() makes them
        self.max_boxes = max_boxes = max(len(a.boxes) for a in arenas) if max_boxes is None else max_boxes
        built: dict[tuple[ArenaSpec, bool], AmosII] = {}  # worlds of one arena share its model (a seed sweep: one)
        for cfg, arena in zip(configs, arenas, strict=True):
            if (arena, cfg.climbing) not in built:  # the body options and the rate are the call's (check above)
                body = make_body(
                    cfg.body,
                    arena,
                    cfg.body_opts,
                    control_hz=cfg.control_hz,
                    climbing=cfg.climbing,
                    pad_boxes=max_boxes,
                )
                assert isinstance(body, AmosII)  # the engine runs AMOSII only (its check above)
                built[arena, cfg.climbing] = body
        bodies = [built[a, c.climbing] for a, c in zip(arenas, configs, strict=True)]
        self.models: list[mujoco.MjModel] = [b.model for b in bodies]
        super().__init__(
            configs,
            arenas,
            self.models[0],
            bodies[0].params,
            bodies[0].n_substeps,
            compiled,
        )
        batch = mujoco.batch.Batch(self.models[0], self.n, nthread, persistent)
        batch.set_models(self.models)
        self.bind_batch(batch)


class MujocoBatch(LockstepEngine):
    """The ``mujoco.batch`` engine: lock-step AMOSII worlds on ``options.threads`` CPU threads, bit for bit the
    CPU loop's runs."""

    name = "mujoco.batch"

    def worlds_per_call(self, options: EngineOptions) -> int | None:
        """16 worlds a call, as Warp's CPU device takes: a call keeps every world's recorded rows in memory, and
        the CPU's few threads gain nothing from more."""
        return 16

    def run(self, configs: Sequence[EpisodeConfig], options: EngineOptions) -> list[Episode]:
        """One episode per config (:class:`MujocoBatchWorlds`)."""
        return MujocoBatchWorlds(configs, nthread=options.threads, max_boxes=options.pad_boxes).run(
            progress=options.progress
        )


def run_batch(
    configs: Sequence[EpisodeConfig], *, nthread: int = 2, progress: bool = True, max_boxes: int | None = None
) -> list[Episode]:
    """Run the configs together in one physics batch; episode i is that of ``run_episode(configs[i])``.

    Args:
        configs: the runs (same body ``amosii``, ``control_hz`` and ``steps``).
        nthread: physics threads.
        progress: show a progress bar (control steps of all runs).
        max_boxes: boxes the padded models have room for (default: the most boxes of any arena).

    Returns:
        One :class:`~neurowalk.sim.config.Episode` per config, in order, with the summary of ``run_episode``
        (``wall_time_s``: the batch's wall time divided by the number of runs).
    """
    return MujocoBatch().run(configs, EngineOptions(threads=nthread, progress=progress, pad_boxes=max_boxes))
