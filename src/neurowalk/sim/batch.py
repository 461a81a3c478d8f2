"""Many runs at once: one padded AMOSII model per arena, all stepped together by ``mujoco.batch``.

.. code-block:: text

    models  = AmosII(arena_i, pad_boxes=max_boxes).model   # same sizes for all (body/obstacle_slots.py)
    batch   = mujoco.batch.Batch(models[0], n, nthread); batch.set_models(models)
    reset:  stand keyframe at each arena's start pose; noise and controllers from each run's seeds()
    each control step:
        read sensordata of all copies -> noisy ultrasonic distances (n, 2)   # as AmosII.observe
        controllers: one compiled call for all copies                       # sim/batch_control.py
        ctrl[:] = targets; batch.step(nstep=n_substeps)                     # on nthread threads
        record

Copy i gives exactly (bit for bit) the trajectory of ``run_episode(configs[i])``: the padded model's physics
is the plain model's (see ``obstacle_slots``), the reset is AmosII.reset's, the noise draws come from the same
Generators in the same order, the controllers run the same kernels, and MuJoCo's batch is bit-identical to a
loop over one ``MjData`` per copy. tests/sim/test_batch.py checks it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import mujoco
import mujoco.batch
import numpy as np

from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.body.amosii import joint_qpos_indices
from neurowalk.body.amosii_params import STAND_KEY, BodyParams
from neurowalk.body.amosii_sensors import sensor_layout
from neurowalk.body.noise import ColoredNoise
from neurowalk.body.physics import AmosII
from neurowalk.observation import Observation
from neurowalk.sim.batch_control import BatchControllers
from neurowalk.sim.episode import Episode, EpisodeConfig, build, seeds, summarize
from neurowalk.sim.trajectory import Trajectory, poses_from_qpos, up_z_from_qpos

__all__ = ["BatchEpisodes", "measure_throughput", "run_batch"]


class BatchEpisodes:
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
        self.configs = list(configs)
        _check(self.configs)
        n = len(self.configs)
        if max_boxes is None:  # the arenas alone, as build() makes them, to size the padding
            max_boxes = max(len(make_arena(c.arena, rng=seeds(c)[2], **c.arena_opts).boxes) for c in self.configs)
        self.max_boxes = max_boxes
        parts = [build(cfg, pad_boxes=max_boxes) for cfg in self.configs]
        self.arenas: list[ArenaSpec] = [p[0] for p in parts]
        bodies = [p[1] for p in parts]
        assert all(isinstance(b, AmosII) for b in bodies)
        self.models: list[mujoco.MjModel] = [b.model for b in bodies]
        self.batch = mujoco.batch.Batch(self.models[0], n, nthread, persistent)
        self.batch.set_models(self.models)
        self._setup(
            self.models[0],
            bodies[0].params,
            bodies[0].n_substeps,
            [p[2] for p in parts],
            [b._noise for b in bodies],
            compiled,
        )  # the bodies' own noise sources: the single loop's draws
        self._qpos, self._ctrl = self.batch.bind("qpos"), self.batch.bind("ctrl")
        self._sensordata, self._time = self.batch.bind("sensordata"), self.batch.bind("time")
        if not self.controllers.compiled:  # act() needs the pose; bound now, as outputs fill only after a call
            self._xpos, self._xmat = self.batch.bind("xpos"), self.batch.bind("xmat")

    def _setup(
        self,
        model: mujoco.MjModel,
        params: BodyParams,
        n_substeps: int,
        controllers: Sequence[Any],
        noises: list[ColoredNoise],
        compiled: bool,
    ) -> None:
        """What every engine shares: the model's sensor layout, the controllers, the noise sources, the timers."""
        self.model, self.params, self.n_substeps = model, params, n_substeps
        self.controllers = BatchControllers(controllers, compiled=compiled)
        self._noise = noises
        lay = sensor_layout(model)
        self._us_adr, self._touch_adr, self._force_full, self._us_max = lay.us, lay.touch, lay.force_full, lay.us_range
        self._us_range = params.us_range
        self._qidx = joint_qpos_indices(model)
        self._trunk = lay.trunk
        self._key = model.key(STAND_KEY).id
        self._n_noise = 2 + len(self._qidx) + 6
        self._noise_now = np.zeros((len(noises), self._n_noise))
        self.timing = {"physics": 0.0, "control": 0.0}

    @property
    def n(self) -> int:
        """Number of runs."""
        return len(self.configs)

    def reset(self) -> None:
        """Every copy standing at its arena's start pose, at rest; noise and controllers from each run's seeds."""
        self._reset_physics()
        rngs = [seeds(cfg) for cfg in self.configs]
        for noise, (body_rng, _, _) in zip(self._noise, rngs, strict=True):
            noise.reset(body_rng)
        self.controllers.reset([ctrl_rng for _, ctrl_rng, _ in rngs])

    def _reset_physics(self) -> None:
        """Every copy's MuJoCo state: the stand keyframe at its arena's start pose, forward-computed."""
        self.batch.reset(keyframe=self._key, stage=mujoco.mjtStage.mjSTAGE_NONE)
        for i, arena in enumerate(self.arenas):
            self._qpos[i, 0:2], self._qpos[i, 3:7] = start_qpos(arena.start)
        self.batch.forward()

    def _advance(self, targets: np.ndarray) -> None:
        """Set every copy's joint targets (n, nu) and step the physics one control step."""
        self._ctrl[:] = targets
        self.batch.step(nstep=self.n_substeps)

    def sense(self) -> tuple[np.ndarray, np.ndarray]:
        """Noisy ultrasonic distances (n, 2) in m (inf = no echo) and foot contacts (n, 6), as AmosII.observe.

        Advances every copy's sensor noise by one control step (kept, with the readings, for :meth:`observation`).
        """
        noise = self._noise_now
        for i, source in enumerate(self._noise):
            noise[i] = source.step()
        sd = self._sensordata
        d = sd[:, self._us_adr]
        raw = np.where((d < 0.0) | (d > self._us_max), np.inf, d)  # read_us
        us = np.maximum(0.0, 1.0 - raw / self._us_range) + noise[:, 0:2]
        dist = np.where(us > 0.0, self._us_range * (1.0 - us), np.inf)
        contact = np.minimum(sd[:, self._touch_adr] / self._force_full, 1.0)  # foot_contacts
        foot = np.clip(contact + noise[:, 2 + len(self._qidx) :], 0.0, 1.0)
        self._sensed = (dist, foot)
        return dist, foot

    def observation(self, i: int) -> Observation:
        """Copy i's full observation of this step (after :meth:`sense`), for controllers stepped by ``act``."""
        nj = len(self._qidx)
        dist, foot = self._sensed
        xpos, xmat = self._xpos[i, self._trunk], self._xmat[i, self._trunk]
        return Observation(
            us_distance=dist[i].copy(),
            foot_contact=foot[i].copy(),
            joint_angles=self._qpos[i, self._qidx] + self._noise_now[i, 2 : 2 + nj],
            pose=np.array([xpos[0], xpos[1], math.atan2(xmat[3], xmat[0])]),
            time=float(self._time[i]),
        )

    def run(self, *, progress: bool = False) -> list[Episode]:
        """Reset, run every copy for its config's steps, and return one :class:`Episode` per config.

        Each episode's ``wall_time_s`` is the batch's wall time divided by the number of runs. Stopped part-way
        (KeyboardInterrupt, e.g. Ctrl-C or SIGTERM in the CLI) it returns the episodes of the completed steps, each
        with ``summary["completed"]`` false (none completed: the interrupt is raised).
        """
        steps, n = self.configs[0].steps, self.n
        shapes = {
            "t": (),
            "inputs": (2,),
            "outputs": (2,),
            "b": (2,),
            "q": (2,),
            "targets": (self.model.nu,),
            "us_distance": (2,),
            "foot_contact": (6,),
            "qpos": (self.model.nq,),
        }
        rec = {name: np.full((steps, n, *shape), np.nan) for name, shape in shapes.items()}
        bar = _progress(steps, n, progress, self.label())
        t0 = time.perf_counter()
        self.reset()
        try:
            done = self._loop(steps, n, rec, bar)
        except KeyboardInterrupt:
            done = int(np.count_nonzero(~np.isnan(rec["t"][:, 0])))  # rows with a time are complete
            if not done:
                raise
            rec = {name: a[:done] for name, a in rec.items()}
        if bar is not None:
            bar.close()
        wall = (time.perf_counter() - t0) / n
        return [self._episode(i, rec, wall) for i in range(n)]

    def _loop(self, steps: int, n: int, rec: dict[str, np.ndarray], bar: Any) -> int:
        """The control steps, recording into ``rec``; returns the number of steps done."""
        ctl = self.controllers
        for k in range(steps):
            tc = time.perf_counter()
            dist, foot = self.sense()
            targets = ctl.step(dist, self.observation)
            tp = time.perf_counter()
            self._advance(targets)
            tr = time.perf_counter()
            rec["inputs"][k], rec["outputs"][k], rec["b"][k], rec["q"][k] = ctl.inputs, ctl.outputs, ctl.b, ctl.q
            rec["targets"][k], rec["us_distance"][k], rec["foot_contact"][k] = targets, dist, foot
            rec["qpos"][k] = self._qpos
            rec["t"][k] = self._time  # last: a row with a time is complete
            self.timing["physics"] += tr - tp
            self.timing["control"] += (tp - tc) + (time.perf_counter() - tr)
            if bar is not None and k % 10 == 9:
                bar.update(10 * n)
        return steps

    def label(self) -> str:
        """What the progress bar calls this run."""
        return f"batch of {self.n}"

    def warnings(self, i: int) -> dict[str, int]:
        """MuJoCo warnings of copy i so far, by name (empty when none)."""
        counts = self.batch.warning[i, :, 1]
        return {mujoco.mjtWarning(w).name: int(c) for w, c in enumerate(counts) if c}

    def _episode(self, i: int, rec: dict[str, np.ndarray], wall: float) -> Episode:
        cfg, arena = self.configs[i], self.arenas[i]
        cols = {name: np.ascontiguousarray(a[:, i]) for name, a in rec.items()}
        q = cols["qpos"]
        tr = Trajectory(
            pose=poses_from_qpos(q), joint_angles=np.ascontiguousarray(q[:, self._qidx]), up_z=up_z_from_qpos(q), **cols
        )
        done = len(q)
        run_cfg = cfg if done == cfg.steps else replace(cfg, steps=done)  # the summary of the steps done
        summary = summarize(run_cfg, arena, tr, wall, self.warnings(i))
        summary["completed"] = done == cfg.steps
        summary["steps_requested"] = cfg.steps
        return Episode(cfg, arena, tr, summary)


def start_qpos(start: tuple[float, float, float]) -> tuple[tuple[float, float], tuple[float, float, float, float]]:
    """The free joint's position (x, y) and quaternion (w, x, y, z) of an arena's start pose (x m, y m, yaw rad)."""
    x, y, yaw = start
    return (x, y), (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))


def _check(configs: list[EpisodeConfig]) -> None:
    check_batch(configs, "a batch", lambda c: c.body == "amosii", "runs body 'amosii' only, got body {!r}", "body")


def check_batch(configs: Sequence[EpisodeConfig], what: str, fits: Any, wrong: str, field: str) -> None:
    """ValueError unless ``configs`` is not empty, every config ``fits`` (else ``what wrong`` with the first misfit's
    ``field``) and all share ``control_hz`` and ``steps``."""
    if not configs:
        raise ValueError(f"{what} needs at least one config")
    bad = [c for c in configs if not fits(c)]
    if bad:
        raise ValueError(f"{what} {wrong.format(getattr(bad[0], field))}")
    for name in ("control_hz", "steps"):
        values = sorted({getattr(c, name) for c in configs})
        if len(values) > 1:
            raise ValueError(f"every config of {what} needs the same {name}, got {values}")


def _progress(steps: int, n: int, on: bool, desc: str) -> Any:
    if not on:
        return None
    from tqdm import tqdm

    return tqdm(total=steps * n, unit="step", desc=desc, mininterval=0.5, smoothing=0.1)


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
        One :class:`~neurowalk.sim.episode.Episode` per config, in order, with the summary of ``run_episode``
        (``wall_time_s``: the batch's wall time divided by the number of runs).
    """
    return BatchEpisodes(configs, nthread=nthread, max_boxes=max_boxes).run(progress=progress)


def measure_throughput(
    n_copies: int = 8,
    steps: int = 300,
    nthread: int = 2,
    *,
    arena: str = "random",
    controller: str = "plastic",
    baseline: bool = True,
) -> dict[str, Any]:
    """Physics throughput of a batch against the single loop on the same runs, measured side by side.

    Runs ``n_copies`` configs (seeds 0, 1, ...) of ``arena`` and ``controller`` for ``steps`` control steps
    as one batch on ``nthread`` threads and, if ``baseline``, one after another with ``run_episode``. Wall
    times exclude building (model compilation, arenas); the first batch call also compiles the controller
    kernels if numba's cache is cold, so call it once before timing anything that matters.

    Returns:
        A JSON-able dict: ``n_copies``, ``steps``, ``nthread``, ``n_substeps``, ``physics_steps`` (all copies),
        ``batch_wall_s``, ``batch_build_s``, ``batch_physics_s`` / ``batch_control_s`` (time in
        ``Batch.step`` / in sensing, controllers and recording), ``batch_physics_steps_per_s`` (aggregate,
        whole loop), and with the baseline ``single_wall_s``, ``single_physics_steps_per_s`` and
        ``speedup`` (single wall time / batch wall time).
    """
    configs = [EpisodeConfig(arena=arena, controller=controller, steps=steps, seed=s) for s in range(n_copies)]
    t0 = time.perf_counter()
    be = BatchEpisodes(configs, nthread=nthread)
    t1 = time.perf_counter()
    be.run()
    wall = time.perf_counter() - t1
    physics_steps = n_copies * steps * be.n_substeps
    out: dict[str, Any] = {
        "n_copies": n_copies,
        "steps": steps,
        "nthread": nthread,
        "arena": arena,
        "controller": controller,
        "n_substeps": be.n_substeps,
        "physics_steps": physics_steps,
        "batch_wall_s": wall,
        "batch_build_s": t1 - t0,
        "batch_physics_s": be.timing["physics"],
        "batch_control_s": be.timing["control"],
        "batch_physics_steps_per_s": physics_steps / wall,
    }
    if baseline:
        from neurowalk.sim.episode import run_episode

        single = sum(run_episode(cfg).summary["wall_time_s"] for cfg in configs)
        out.update(single_wall_s=single, single_physics_steps_per_s=physics_steps / single, speedup=single / wall)
    return out
