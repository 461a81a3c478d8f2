"""Lock-step worlds: many AMOSII runs stepped together, the physics plugged in.

.. code-block:: text

    reset:  physics.reset (each world at its arena's start pose); noise and controllers from each run's seeds()
    each control step:
        sensordata of all worlds -> noisy ultrasonic distances (n, 2)   # body.common, as AmosII.observe
        controllers: one compiled call for all worlds                   # sim/batch_control.py
        physics.advance(targets)                                        # mujoco.batch threads, or MuJoCo Warp
        record

:class:`LockstepWorlds` writes the sensing, the sensor noise, the controllers and the recording once; a subclass
plugs in the physics (:meth:`~LockstepWorlds.reset_physics`, :meth:`~LockstepWorlds.advance`,
:meth:`~LockstepWorlds.warnings`) and fills :attr:`qpos`, :attr:`sensordata` and :attr:`sim_time` after each
reset and step. :class:`LockstepEngine` is the engine interface over such worlds: configs of one group (same steps
and control rate) share one call.
"""

from __future__ import annotations

import math
import time
from abc import ABC, abstractmethod
from collections.abc import Hashable, Mapping, Sequence
from typing import Any

import mujoco
import numpy as np

from neurowalk.arenas import ArenaSpec
from neurowalk.body.amosii_params import STAND_KEY, BodyParams
from neurowalk.body.amosii_sensors import joint_qpos_indices, sensed, sensor_layout
from neurowalk.body.noise import ColoredNoise, ColoredNoiseBatch
from neurowalk.body.registry import BODIES
from neurowalk.observation import Observation
from neurowalk.progress import Progress
from neurowalk.sim.batch_control import BatchControllers
from neurowalk.sim.config import Episode, EpisodeConfig, build_controller, progress_bar, seeds
from neurowalk.sim.engine_interface import Engine, EngineOptions
from neurowalk.sim.recorder import derive_columns, finish_episode, in_region
from neurowalk.sim.trajectory import Trajectory

__all__ = ["LockstepEngine", "LockstepWorlds"]

#: The bodies lock-step worlds run: one model structure for every arena (obstacle slots; body/obstacle_slots.py).
LOCKSTEP_BODIES = tuple(name for name, info in BODIES.items() if info.lockstep)


class LockstepWorlds(ABC):
    """n runs of AMOSII (one per config) stepped together; the physics is a subclass's.

    Args:
        configs: the runs (one group: same ``steps`` and ``control_hz``).
        arenas: each run's arena.
        model: the CPU ``MjModel`` of world 0 (sizes, names, sensor addresses; every world has its structure).
        params: the body's numbers. n_substeps: physics steps per control step.
        compiled: step the controllers in one compiled call (else each controller's ``act``).

    Each run's controller is its config's (:func:`~neurowalk.sim.config.build_controller`) and its sensor noise
    AMOSII's own source (2 ultrasonic, the joints and 6 feet channels, its config's ``noise`` strength).

    Attributes:
        qpos (n, nq), sensordata (n, nsensordata), sim_time (n,): the worlds' state after the last reset or step
            (the subclass fills them). timing: seconds in ``physics`` and in ``control``, the host's part, which is
            ``sense`` (sensor model and noise) + ``controllers`` + ``record``.
    """

    def __init__(
        self,
        configs: Sequence[EpisodeConfig],
        arenas: Sequence[ArenaSpec],
        model: mujoco.MjModel,
        params: BodyParams,
        n_substeps: int,
        compiled: bool,
    ) -> None:
        self.configs, self.arenas = list(configs), list(arenas)
        self.model, self.params, self.n_substeps = model, params, n_substeps
        self.controllers = BatchControllers([build_controller(c) for c in configs], compiled=compiled)
        self.layout = lay = sensor_layout(model)
        self.us_range = params.us_range
        self.qidx = joint_qpos_indices(model)
        channels = 2 + len(self.qidx) + 6  # as AmosII's own source
        sources = [ColoredNoise(channels, strength=c.noise) for c in self.configs]
        self.noise = ColoredNoiseBatch(sources)  # every world's sensor noise, one array step for all
        self.trunk = lay.trunk
        self.stand_key = model.key(STAND_KEY).id
        self.noise_now = self.noise.value  # (n, 2 + joints + 6): this step's noise of every world
        self.timing = dict.fromkeys(("physics", "control", "sense", "controllers", "record"), 0.0)
        self.qpos: np.ndarray = np.zeros((self.n, model.nq))
        self.sensordata: np.ndarray = np.zeros((self.n, model.nsensordata))
        self.sim_time: np.ndarray = np.zeros(self.n)
        self.xpos: np.ndarray | None = None  # (n, nbody, 3), (n, nbody, 9): for controllers stepped by act()
        self.xmat: np.ndarray | None = None
        self._sensed: tuple[np.ndarray, np.ndarray] | None = None

    @property
    def n(self) -> int:
        """Number of runs."""
        return len(self.configs)

    @abstractmethod
    def reset_physics(self) -> None:
        """Every world standing at its arena's start pose (``place_at_start``), at rest, forward-computed."""

    @abstractmethod
    def advance(self, targets: np.ndarray) -> None:
        """Set every world's joint targets (n, nu) and step the physics one control step."""

    @abstractmethod
    def warnings(self, i: int) -> dict[str, int]:
        """World i's warnings so far, by name (empty when none)."""

    def label(self) -> str:
        """What the progress bar calls this run."""
        return f"batch of {self.n}"

    def reset(self) -> None:
        """Every world at its start pose, at rest; noise and controllers from each run's seeds."""
        self.reset_physics()
        rngs = [seeds(cfg) for cfg in self.configs]
        self.noise.reset([body_rng for body_rng, _, _ in rngs])
        self.controllers.reset([ctrl_rng for _, ctrl_rng, _ in rngs])

    def sense(self) -> tuple[np.ndarray, np.ndarray]:
        """Noisy ultrasonic distances (n, 2) in m (inf = no echo) and foot contacts (n, 6), as AmosII.observe.

        Advances every world's sensor noise by one control step (kept, with the readings, for :meth:`observation`).
        """
        noise = self.noise.step()
        dist, foot = sensed(self.layout, self.sensordata, self.us_range, noise)  # AmosII.observe's sensor model
        self._sensed = (dist, foot)
        return dist, foot

    def observation(self, i: int) -> Observation:
        """World i's full observation of this step (after :meth:`sense`), for controllers stepped by ``act``."""
        assert self._sensed is not None and self.xpos is not None and self.xmat is not None
        nj = len(self.qidx)
        dist, foot = self._sensed
        xpos, xmat = self.xpos[i, self.trunk], self.xmat[i, self.trunk]
        return Observation(
            us_distance=dist[i].copy(),
            foot_contact=foot[i].copy(),
            joint_angles=self.qpos[i, self.qidx] + self.noise_now[i, 2 : 2 + nj],
            pose=np.array([xpos[0], xpos[1], math.atan2(xmat[3], xmat[0])]),
            time=float(self.sim_time[i]),
        )

    def run(self, *, progress: bool = False) -> list[Episode]:
        """Reset, run every world for its config's steps, and return one :class:`Episode` per config.

        Each episode's ``wall_time_s`` is the whole run's wall time divided by the number of runs. Stopped part-way
        (KeyboardInterrupt, e.g. Ctrl-C or SIGTERM in the CLI) it returns the episodes of the completed steps, each
        with ``summary["completed"]`` false (none completed: the interrupt is raised).
        """
        steps, n = self.configs[0].steps, self.n
        shapes = Trajectory.shapes(self.model.nq)
        rec = {name: np.full((steps, n, *shapes[name]), np.nan) for name in Trajectory.RECORDED}
        bar = progress_bar(steps * n, progress, self.label())
        t0 = time.perf_counter()
        self.reset()
        try:
            done = self._loop(steps, rec, bar)
        except KeyboardInterrupt:
            done = int(np.count_nonzero(~np.isnan(rec["t"][:, 0])))  # rows with a time are complete
            if not done:
                raise
        if done < steps:
            rec = {name: a[:done] for name, a in rec.items()}
        if bar is not None:
            bar.close()
        wall = (time.perf_counter() - t0) / n
        return [self._episode(i, rec, wall) for i in range(n)]

    def _loop(self, steps: int, rec: dict[str, np.ndarray], bar: Progress | None) -> int:
        """The control steps, recording into ``rec``; returns the steps run: fewer than ``steps`` where every world
        stops by its config's ``until`` rule before (each world's episode ends where its own rule says)."""
        ctl, n, timing = self.controllers, self.n, self.timing
        pairs = zip(self.configs, self.arenas, strict=True)
        regions = [a.exit_region for c, a in pairs if c.until == "escaped" and a.exit_region is not None]
        stopping = len(regions) == n  # every world stops by its rule: the call ends when the last has stopped
        bounds = tuple(np.array(regions).T) if stopping else ()  # (x0, x1, y0, y1), each (n,)
        stopped = np.zeros(n, dtype=bool)
        for k in range(steps):
            t0 = time.perf_counter()
            dist, foot = self.sense()
            t1 = time.perf_counter()
            targets = ctl.step(dist, self.observation)
            t2 = time.perf_counter()
            self.advance(targets)
            t3 = time.perf_counter()
            rec["inputs"][k], rec["outputs"][k], rec["b"][k], rec["q"][k] = ctl.inputs, ctl.outputs, ctl.b, ctl.q
            rec["targets"][k], rec["us_distance"][k], rec["foot_contact"][k] = targets, dist, foot
            rec["qpos"][k] = self.qpos
            rec["t"][k] = self.sim_time  # last: a row with a time is complete
            t4 = time.perf_counter()
            timing["physics"] += t3 - t2
            timing["control"] += (t2 - t0) + (t4 - t3)
            timing["sense"] += t1 - t0
            timing["controllers"] += t2 - t1
            timing["record"] += t4 - t3
            if bar is not None and k % 10 == 9:
                bar.update(10 * n)
            if stopping:
                stopped |= in_region(self.qpos[:, 0], self.qpos[:, 1], bounds)  # every world in one array step
                if stopped.all():
                    return k + 1
        return steps

    def _episode(self, i: int, rec: dict[str, np.ndarray], wall: float) -> Episode:
        """World i's episode; with ``until="escaped"`` it ends at the first step whose trunk centre is in the exit
        region, as the CPU loop's run of its config does."""
        cfg, arena = self.configs[i], self.arenas[i]
        done, stopped = len(rec["t"]), False
        region = arena.exit_region if cfg.until == "escaped" else None
        if region is not None:
            inside = np.flatnonzero(in_region(rec["qpos"][:done, i, 0], rec["qpos"][:done, i, 1], region))
            if len(inside):
                done, stopped = int(inside[0]) + 1, True
        tr = Trajectory.empty(done, self.model.nq)
        for name, a in rec.items():
            getattr(tr, name)[:] = a[:done, i]
        derive_columns(tr, self.qidx - 7, 0, done)  # pose, joint angles and up_z, as the CPU loop's recorder does
        return finish_episode(cfg, arena, tr, done, wall, self.warnings(i), stopped=stopped)


class LockstepEngine(Engine):
    """Engines over lock-step worlds: many worlds per call; configs of one group (steps, control rate) share it."""

    many_worlds = True

    def check(self, configs: Sequence[EpisodeConfig], options: EngineOptions) -> None:
        """ValueError unless every config runs a lock-step body and all share this engine's group key."""
        super().check(configs, options)
        bad = [c for c in configs if c.body not in LOCKSTEP_BODIES]
        if bad:
            runs = ", ".join(repr(b) for b in LOCKSTEP_BODIES)
            raise ValueError(f"engine {self.name!r} runs body {runs} only, got body {bad[0].body!r}")
        for name in ("control_hz", "steps", "body_opts"):
            values = sorted({repr(_hashable(getattr(c, name))) for c in configs})
            if len(values) > 1:
                raise ValueError(
                    f"every config of one call of engine {self.name!r} needs the same {name}, got {', '.join(values)}"
                )

    def group_key(self, cfg: EpisodeConfig) -> Hashable:
        """Configs of the same length, control rate and body options run as one call's worlds."""
        return (cfg.steps, cfg.control_hz, _hashable(cfg.body_opts))


def _hashable(v: Any) -> Any:
    """``v`` with its mappings as sorted tuples of items (a group key's part)."""
    return tuple(sorted(v.items())) if isinstance(v, Mapping) else v
