"""Physics on MuJoCo Warp: many AMOSII worlds in one model, on a GPU (or Warp's CPU device), one control loop.

.. code-block:: text

    model   = AMOSII + n_slots world boxes (body/obstacle_slots.slot_world)      # one structure for all arenas
    warp    = mujoco_warp.put_model(model, batch_sizes={geom_pos, quat, size, aabb, rbound: nworld})
              each world's obstacle rows from its own arena (slot_rows)       # Table 2 environments differ
    each control step (as sim/batch.py):
        sensordata of all worlds -> noisy distances (n, 2); controllers: one compiled call for all worlds
        ctrl <- targets; n_substeps x mujoco_warp.step (one CUDA graph on a GPU); qpos, sensordata, time -> host

The sensing, noise, controllers and recording are :class:`~neurowalk.sim.batch.BatchEpisodes`'; only the physics
differs. Warp computes in float32, MuJoCo in float64: a world follows the CPU run closely for a while (joint
positions within about 1e-6 rad after 200 physics steps) and then drifts apart as any two contact-rich runs do,
so single runs agree in behaviour and statistics, not bit for bit (tests/sim/test_warp_engine.py states the
tolerances). On Warp's CPU device a run is repeatable; on a GPU the order of contacts may vary.

The engine needs the ``warp`` extra (``pip install 'neurowalk[warp]'``: ``mujoco-warp``, ``warp-lang``).
Device: ``cuda`` where a CUDA GPU is present, else ``cpu`` with a warning (about 100-1000x slower than CPU
MuJoCo: for tests and checks); ``NEUROWALK_WARP_DEVICE`` or ``--device`` chooses.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np

from neurowalk.arenas import make_arena
from neurowalk.body.amosii import amosii_xml, joint_qpos_indices
from neurowalk.body.amosii_params import BodyParams
from neurowalk.body.noise import ColoredNoise
from neurowalk.body.obstacle_slots import slot_rows, slot_world
from neurowalk.body.physics import n_substeps as substeps_of
from neurowalk.sim.batch import BatchEpisodes, check_batch, start_qpos
from neurowalk.sim.config import Episode, EpisodeConfig, build_controller, seeds

__all__ = ["DEVICE_ENV", "WarpEpisodes", "import_warp", "resolve_device", "run_warp"]

DEVICE_ENV = "NEUROWALK_WARP_DEVICE"
"""Environment variable naming the Warp device (``cpu`` or ``cuda``) when none is given."""
GEOM_FIELDS = ("pos", "quat", "size", "aabb", "rbound")  # the obstacle rows batched per world


def import_warp() -> tuple[Any, Any]:
    """``(warp, mujoco_warp)``; ValueError with the install line when the ``warp`` extra is missing."""
    try:
        import warp

        warp.config.log_level = warp.LOG_ERROR  # no banner, no module-load lines (we name the device ourselves)
        import mujoco_warp
    except ImportError as e:
        raise ValueError(f"engine 'warp' needs the warp extra: pip install 'neurowalk[warp]' ({e})") from e
    return warp, mujoco_warp


def resolve_device(device: str | None = None) -> str:
    """The Warp device to run on: ``device``, else $NEUROWALK_WARP_DEVICE, else ``cuda`` if present, else ``cpu``.

    Raises:
        ValueError: a device other than cpu/cuda, cuda without a CUDA GPU, or the extra missing.
    """
    wp, _ = import_warp()
    device = device or os.environ.get(DEVICE_ENV) or None
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
    import tempfile

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
    import platform

    return platform.processor() or platform.machine()


class WarpEpisodes(BatchEpisodes):
    """n runs of AMOSII (one per config) as the worlds of one MuJoCo Warp model.

    Args:
        configs: the runs: engine ``warp``, body ``amosii``, the same ``control_hz`` and ``steps``; arenas,
            seeds, controllers, variants and noise may differ.
        device: ``cpu`` or ``cuda`` (default: :func:`resolve_device`).
        max_boxes: obstacle slots (default: the most boxes of any arena).
        nconmax, njmax: contacts and constraint rows allocated per world.

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
    ) -> None:
        self.configs = list(configs)
        _check(self.configs)
        self.device = resolve_device(device)
        self._wp, self._mjw = import_warp()
        wp, mjw = self._wp, self._mjw
        n = len(self.configs)
        self.arenas = [make_arena(c.arena, rng=seeds(c)[2], **c.arena_opts) for c in self.configs]
        self.max_boxes = max_boxes if max_boxes is not None else max(len(a.boxes) for a in self.arenas)
        params = BodyParams()
        model = mujoco.MjModel.from_xml_string(amosii_xml(params, world=slot_world(self.arenas[0], self.max_boxes)))
        nj = len(joint_qpos_indices(model))
        noises = [ColoredNoise(2 + nj + 6, strength=c.noise) for c in self.configs]  # as AmosII's own source
        self._setup(
            model,
            params,
            substeps_of(self.configs[0].control_hz, model.opt.timestep),
            [build_controller(c) for c in self.configs],
            noises,
            compiled,
        )
        if not self.controllers.compiled:
            raise ValueError("engine 'warp' steps the controllers compiled only (plastic, static, braitenberg, fixed)")
        slots = np.array([model.geom(f"obstacle_{k}").id for k in range(self.max_boxes)], dtype=int)
        rows = [slot_rows(a, self.max_boxes) for a in self.arenas]
        with wp.ScopedDevice(self.device):
            self.wmodel = mjw.put_model(model, batch_sizes={f"geom_{f}": n for f in GEOM_FIELDS})
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
        self._qpos = np.zeros((n, model.nq))
        self._sensordata = np.zeros((n, model.nsensordata))
        self._time = np.zeros(n)
        self._graph: Any = None

    def _reset_physics(self) -> None:
        wp, mjw, d, m = self._wp, self._mjw, self.wdata, self.model
        key = m.key(self._key)
        qpos = np.tile(key.qpos, (self.n, 1))
        for i, arena in enumerate(self.arenas):
            qpos[i, 0:2], qpos[i, 3:7] = start_qpos(arena.start)
        with wp.ScopedDevice(self.device):
            mjw.reset_data(self.wmodel, d)
            d.qpos.assign(qpos)
            d.qvel.zero_()
            d.ctrl.assign(np.tile(key.ctrl, (self.n, 1)))
            d.time.fill_(float(key.time[0]))
            for name, rows in (("geom_xpos", self._slot_xpos), ("geom_xmat", self._slot_xmat)):
                full = getattr(d, name).numpy()
                full[:, self._slots] = rows
                getattr(d, name).assign(full)
            mjw.forward(self.wmodel, d)
        self._t0, self._k = float(key.time[0]), 0
        self._pull()

    def _advance(self, targets: np.ndarray) -> None:
        wp, mjw = self._wp, self._mjw
        with wp.ScopedDevice(self.device):
            self.wdata.ctrl.assign(np.asarray(targets, dtype=np.float32))
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
        self._qpos[:] = d.qpos.numpy()
        self._sensordata[:] = d.sensordata.numpy()
        self._time[:] = self._t0 + self._k * self.n_substeps * self.model.opt.timestep

    def label(self) -> str:
        """What the progress bar calls this run: the engine, the device and the worlds."""
        return f"warp {self.device}, {self.n} world{'s' if self.n > 1 else ''}"

    def warnings(self, i: int) -> dict[str, int]:
        """World i's overflow flags so far (contacts or constraints beyond what was allocated), by name."""
        bits = int(self.wdata.overflow.numpy()[i]) if hasattr(self.wdata, "overflow") else 0
        if not bits:
            return {}
        from mujoco_warp import OverflowType

        return {f"WARP_OVERFLOW_{o.name}": 1 for o in OverflowType if o.value and o.name != "ALL" and bits & o.value}


def _yaw_matrices(quat: np.ndarray) -> np.ndarray:
    """Rotation matrices (k, 3, 3) of quaternions (k, 4) (w, x, y, z) that turn about z only."""
    yaw = 2.0 * np.arctan2(quat[:, 3], quat[:, 0])
    c, s = np.cos(yaw), np.sin(yaw)
    out = np.zeros((len(quat), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 1, 0], out[:, 1, 1], out[:, 2, 2] = c, -s, s, c, 1.0
    return out


def _check(configs: list[EpisodeConfig]) -> None:
    check_batch(
        configs, "a Warp run", lambda c: c.engine == "warp", "runs configs with engine 'warp', got {!r}", "engine"
    )


def run_warp(
    configs: Sequence[EpisodeConfig], *, device: str | None = None, progress: bool = True, max_boxes: int | None = None
) -> list[Episode]:
    """Run the configs (engine ``warp``) as the worlds of one MuJoCo Warp model; one Episode per config.

    Each episode's summary is that of ``run_episode`` (``wall_time_s``: the whole run's wall time divided by the
    number of worlds), with ``engine`` and ``device`` added.
    """
    runs = WarpEpisodes(configs, device=device, max_boxes=max_boxes)
    episodes = runs.run(progress=progress)
    for ep in episodes:
        ep.summary["engine"], ep.summary["device"] = "warp", runs.device
    return episodes
