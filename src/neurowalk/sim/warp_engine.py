"""Physics on MuJoCo Warp: many AMOSII worlds in one model, on a GPU (or Warp's CPU device), one control loop.

.. code-block:: text

    model   = AMOSII + n_slots world boxes (body/obstacle_slots.slot_world)      # one structure for all arenas
    warp    = mujoco_warp.put_model(model, batch_sizes={geom_pos, quat, size, aabb, rbound: nworld})
              each world's obstacle rows from its own arena (slot_rows)       # Table 2 environments differ
    each control step (as sim/batch.py):
        sensordata of all worlds -> noisy distances (n, 2); controllers: one compiled call for all worlds
        ctrl <- targets; n_substeps x mujoco_warp.step (one CUDA graph on a GPU); qpos, sensordata, time -> host

The sensing, noise, controllers and recording are :class:`~neurowalk.sim.lockstep.LockstepWorlds`'; only the physics
differs. Warp computes in float32, MuJoCo in float64: a world follows the CPU run closely for a while (joint
positions within about 1e-6 rad after 200 physics steps) and then drifts apart as any two contact-rich runs do,
so single runs agree in behaviour and statistics, not bit for bit (tests/sim/test_warp_engine.py states the
tolerances). MuJoCo Warp's deterministic execution is on (``opt.deterministic``): a rerun of the same worlds
repeats bit for bit, on Warp's CPU device and, measured on an H200 (docs/gpu.md), on a GPU; on a GPU a world's
run may still differ in its last bits with the size of the batch beside it (measured: alone and beside one world
equal, beside 64 not).

The engine needs the ``warp`` extra (``pip install -e '.[warp]'`` in neurowalk's folder: ``mujoco-warp``,
``warp-lang``).
Device: ``cuda`` where a CUDA GPU is present, else ``cpu`` with a warning (about 100-1000x slower than CPU
MuJoCo: for tests and checks); ``EngineOptions.device`` (``--device``) chooses.
"""

from __future__ import annotations

import os
import platform
import sys
import tempfile
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import mujoco
import numpy as np

from neurowalk.arenas import make_arena
from neurowalk.body.amosii_mjcf import amosii_xml
from neurowalk.body.common import place_at_start
from neurowalk.body.obstacle_slots import slot_rows, slot_world
from neurowalk.body.physics import set_control_rate
from neurowalk.body.registry import amosii_params
from neurowalk.sim.config import Episode, EpisodeConfig, seeds
from neurowalk.sim.engine_interface import EngineOptions
from neurowalk.sim.lockstep import LockstepEngine, LockstepWorlds

__all__ = ["Warp", "WarpWorlds", "import_warp", "resolve_device", "run_warp"]

GEOM_FIELDS = ("pos", "quat", "size", "aabb", "rbound")  # the obstacle rows batched per world


def import_warp() -> tuple[Any, Any]:
    """``(warp, mujoco_warp)``; ValueError with the install line when the ``warp`` extra is missing."""
    try:
        import warp

        warp.config.log_level = warp.LOG_ERROR  # no banner, no module-load lines (we name the device ourselves)
        import mujoco_warp
    except ImportError as e:
        raise ValueError(
            f"engine 'warp' needs the warp extra: pip install -e '.[warp]' in neurowalk's folder ({e})"
        ) from e
    return warp, mujoco_warp


def resolve_device(device: str | None = None) -> str:
    """The Warp device to run on: ``device``, else ``cuda`` if present, else ``cpu`` (saying so).

    Raises:
        ValueError: a device other than cpu/cuda, cuda without a CUDA GPU, or the extra missing.
    """
    wp, _ = import_warp()
    if device not in (None, "cpu", "cuda"):
        raise ValueError(f"unknown device {device!r}; expected cpu or cuda")
    _init_quietly(wp)
    has_cuda = wp.get_cuda_device_count() > 0
    if device == "cuda" and not has_cuda:
        raise ValueError("device 'cuda' asked for, but Warp finds no CUDA GPU here; use --device cpu (slow)")
    if device is None:
        device = "cuda" if has_cuda else "cpu"
        if device == "cpu":
            print(
                "neurowalk: engine 'warp': no CUDA GPU here, running on Warp's CPU device (slow; --device cpu "
                "to choose it and silence this)",
                file=sys.stderr,
            )
    return device


def _init_quietly(wp: Any) -> None:
    """``wp.init()`` without its native line "Could not find or load the NVIDIA CUDA driver" on a machine with no
    GPU (the device is named by :func:`resolve_device` itself); any other native output is passed on."""
    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            wp.init()
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        tmp.seek(0)
        text = tmp.read().decode(errors="replace")
    rest = [line for line in text.splitlines() if "CUDA driver" not in line and line.strip()]
    if rest:
        print("\n".join(rest), file=sys.stderr)


def device_name(device: str) -> str:
    """A readable name of the Warp device (e.g. the GPU's model)."""
    wp, _ = import_warp()
    return str(wp.get_device(device).name) if device == "cuda" else f"cpu ({_cpu_name()})"


def _cpu_name() -> str:
    return platform.processor() or platform.machine()


class WarpWorlds(LockstepWorlds):
    """n runs of AMOSII (one per config) as the worlds of one MuJoCo Warp model.

    Args:
        configs: the runs: engine ``warp``, body ``amosii``, the same ``control_hz`` and ``steps``; arenas,
            seeds, controllers, variants and noise may differ.
        device: ``cpu`` or ``cuda`` (default: :func:`resolve_device`).
        max_boxes: obstacle slots (default: the most boxes of any arena).
        nconmax, njmax: contacts and constraint rows allocated per world.
        deterministic: MuJoCo Warp's deterministic execution (``opt.deterministic``, all of
            ``mujoco_warp.DeterminismType``: stable contact order, canonical constraint rows, invariant atomic sums),
            so that a rerun repeats bit for bit on a GPU too; off: the faster, run-to-run varying kernels.

    Attributes:
        device: the Warp device. arenas: each world's arena. model: the CPU MjModel of world 0 (sizes, names).
        timing: seconds in ``physics`` (Warp steps and copies) and in ``control``.
    """

    def __init__(
        self,
        configs: Sequence[EpisodeConfig],
        *,
        device: str | None = None,
        max_boxes: int | None = None,
        nconmax: int = 48,
        njmax: int = 256,
        compiled: bool = True,
        deterministic: bool = True,
    ) -> None:
        configs = list(configs)
        Warp().check(configs, EngineOptions(device=device))
        self.device = resolve_device(device)
        self.wp, self.mjw = import_warp()
        wp, mjw = self.wp, self.mjw
        n = len(configs)
        arenas = [make_arena(c.arena, rng=seeds(c)[2], **c.arena_opts) for c in configs]
        self.max_boxes = max_boxes if max_boxes is not None else max(len(a.boxes) for a in arenas)
        params = amosii_params(configs[0].body_opts)  # one call's configs share them (LockstepEngine.check)
        model = mujoco.MjModel.from_xml_string(amosii_xml(params, world=slot_world(arenas[0], self.max_boxes)))
        super().__init__(
            configs,
            arenas,
            model,
            params,
            set_control_rate(model, configs[0].control_hz),
            compiled,
        )
        if not self.controllers.compiled:
            raise ValueError("engine 'warp' steps the controllers compiled only (plastic, static, braitenberg, fixed)")
        slots = np.array([model.geom(f"obstacle_{k}").id for k in range(self.max_boxes)], dtype=int)
        rows = [slot_rows(a, self.max_boxes) for a in self.arenas]
        # Warp's sparse constraint Jacobian does not repeat a run bit for bit; the dense one is the same physics
        model.opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
        with wp.ScopedDevice(self.device):
            self.wmodel = mjw.put_model(model, batch_sizes={f"geom_{f}": n for f in GEOM_FIELDS})
            self.wmodel.opt.deterministic = int(mjw.DeterminismType.ALL if deterministic else mjw.DeterminismType.NONE)
            for f in GEOM_FIELDS:
                arr = getattr(self.wmodel, f"geom_{f}")
                full = np.repeat(arr.numpy()[:1], n, axis=0)
                for w, r in enumerate(rows):
                    full[w, slots] = r[f].reshape(full[w, slots].shape)
                arr.assign(full)
            self.wdata = mjw.make_data(model, nworld=n, nconmax=nconmax, njmax=njmax)
        # world geoms are static: Warp places them once, from world 0's model; each world's own places are set here
        self._slots = slots
        self._slot_xpos = np.stack([r["pos"] for r in rows])
        self._slot_xmat = np.stack([_yaw_matrices(r["quat"]) for r in rows])
        self._graph: Any = None

    def reset_physics(self) -> None:
        """Every world standing at its arena's start pose, at rest, forward-computed (on the device)."""
        wp, mjw, d, m = self.wp, self.mjw, self.wdata, self.model
        key = m.key(self.stand_key)
        qpos = np.tile(key.qpos, (self.n, 1))
        for i, arena in enumerate(self.arenas):
            place_at_start(qpos[i], arena.start)
        with wp.ScopedDevice(self.device):
            mjw.reset_data(self.wmodel, d)
            d.qpos.assign(qpos)
            d.qvel.zero_()
            d.ctrl.assign(np.tile(key.ctrl, (self.n, 1)))
            if m.na:  # the servos' lagged targets (BodyParams.servo_timeconst)
                d.act.assign(np.tile(key.act, (self.n, 1)))
            d.time.fill_(float(key.time[0]))
            for name, rows in (("geom_xpos", self._slot_xpos), ("geom_xmat", self._slot_xmat)):
                full = getattr(d, name).numpy()
                full[:, self._slots] = rows
                getattr(d, name).assign(full)
            mjw.forward(self.wmodel, d)
        self._t0, self._k = float(key.time[0]), 0
        self._pull()

    def apply(self, actions: np.ndarray) -> None:
        """Every world's joint targets (n, nu), rad (float32 on the device)."""
        with self.wp.ScopedDevice(self.device):
            self.wdata.ctrl.assign(np.asarray(actions, dtype=np.float32))

    def advance(self) -> None:
        """``n_substeps`` Warp steps of every world (one CUDA graph on a GPU)."""
        wp, mjw = self.wp, self.mjw
        with wp.ScopedDevice(self.device):
            if self.device == "cuda":
                if self._graph is None:
                    with wp.ScopedCapture() as capture:
                        for _ in range(self.n_substeps):
                            mjw.step(self.wmodel, self.wdata)
                    self._graph = capture.graph
                wp.capture_launch(self._graph)
            else:
                for _ in range(self.n_substeps):
                    mjw.step(self.wmodel, self.wdata)
        self._k += 1
        self._pull()

    def _pull(self) -> None:
        """The worlds' positions and sensor readings onto the host (float64); the time counted in float64 (Warp's
        float32 clock would be 0.2 ms off after an hour simulated)."""
        d = self.wdata
        self.qpos[:] = d.qpos.numpy()
        self.sensordata[:] = d.sensordata.numpy()
        self.sim_time[:] = self._t0 + self._k * self.n_substeps * self.model.opt.timestep

    def label(self) -> str:
        """What the progress bar calls this run: the engine, the device and the worlds."""
        return f"warp {self.device}, {self.n} world{'s' if self.n > 1 else ''}"

    def warnings(self, i: int) -> dict[str, int]:
        """World i's overflow flags so far (contacts or constraints beyond what was allocated), by name."""
        bits = int(self.wdata.overflow.numpy()[i]) if hasattr(self.wdata, "overflow") else 0
        if not bits:
            return {}
        _, mjw = import_warp()
        flags = mjw.OverflowType
        return {f"WARP_OVERFLOW_{o.name}": 1 for o in flags if o.value and o.name != "ALL" and bits & o.value}


def _yaw_matrices(quat: np.ndarray) -> np.ndarray:
    """Rotation matrices (k, 3, 3) of quaternions (k, 4) (w, x, y, z) that turn about z only."""
    yaw = 2.0 * np.arctan2(quat[:, 3], quat[:, 0])
    c, s = np.cos(yaw), np.sin(yaw)
    out = np.zeros((len(quat), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 1, 0], out[:, 1, 1], out[:, 2, 2] = c, -s, s, c, 1.0
    return out


class Warp(LockstepEngine):
    """The MuJoCo Warp engine (``engine="warp"``): lock-step AMOSII worlds on a GPU, or on Warp's CPU device."""

    name = "warp"
    devices = ("cpu", "cuda")

    def worlds_per_call(self, options: EngineOptions) -> int | None:
        """4096 worlds a call on a GPU, 16 on Warp's CPU device."""
        return 4096 if resolve_device(options.device) == "cuda" else 16

    def resolve(self, options: EngineOptions) -> EngineOptions:
        """The device named (checked), or the one found (:func:`resolve_device`); needs the ``warp`` extra."""
        return replace(options, device=resolve_device(options.device))

    def run(self, configs: Sequence[EpisodeConfig], options: EngineOptions) -> list[Episode]:
        """One episode per config, with ``engine`` and ``device`` added to its summary."""
        worlds = WarpWorlds(configs, device=options.device, max_boxes=options.pad_boxes)
        episodes = worlds.run(progress=options.progress)
        for ep in episodes:
            ep.summary["engine"], ep.summary["device"] = self.name, worlds.device
        return episodes


def run_warp(
    configs: Sequence[EpisodeConfig], *, device: str | None = None, progress: bool = True, max_boxes: int | None = None
) -> list[Episode]:
    """Run the configs (engine ``warp``) as the worlds of one MuJoCo Warp model; one Episode per config.

    Each episode's summary is that of ``run_episode`` (``wall_time_s``: the whole run's wall time divided by the
    number of worlds), with ``engine`` and ``device`` added.
    """
    return Warp().run(configs, EngineOptions(device=device, progress=progress, pad_boxes=max_boxes))
