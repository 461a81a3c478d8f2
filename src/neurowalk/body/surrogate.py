"""The planar surrogate of AMOSII: pose (x, y, yaw), the same two ultrasonic rays, the same sensory network.

The legs are not simulated. Each control step the steering (O1, O2) is turned into a body velocity
(forward m/s, lateral m/s, yaw rate rad/s) by bilinear look-up in a table measured on the physics
robot (``neurowalk calibrate``, stored in ``body/data/calibration.json``), delayed and low-passed by
the measured response lag, and integrated; the footprint (circles for trunk and legs, measured from
the MJCF) is pushed out of every box it would enter, so the body slides along walls and never passes
through them. Box heights are ignored: every box is a wall to the surrogate.

The same model, calibrated on the physics wheeled robot (``neurowalk calibrate --body wheeled``, stored in
``body/data/calibration-wheeled.json``), is the body ``surrogate-wheeled``: no gait, so no yaw sway.

The surrogate reads only its data file; :mod:`neurowalk.experiments.calibration` measures and writes it.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body import surrogate_kernel as kern
from neurowalk.neural.sensory import PARAMS_SIZE, STATE_SIZE
from neurowalk.observation import Observation

CALIBRATION_FILE = Path(__file__).with_name("data") / "calibration.json"
CALIBRATION_FILES: dict[str, Path] = {
    "surrogate": CALIBRATION_FILE,  # calibrated on AMOSII
    "surrogate-wheeled": CALIBRATION_FILE.with_name("calibration-wheeled.json"),  # on the wheeled robot
}
"""The shipped calibration of each planar body (registry name -> data file)."""


@dataclass(frozen=True)
class Calibration:
    """What the surrogate knows of the physics robot.

    Attributes:
        grid: (g,) steering values at which the velocity was measured (same for O1 and O2).
        velocity: (g, g, 3) body velocity at steering (grid[i], grid[j]) = (O1, O2): forward m/s, lateral
            m/s (left +), yaw rate rad/s (left +), steady state over whole gait cycles.
        sway: (g, g) amplitude of the trunk's yaw rocking with the gait (rad), at the same steering pairs.
        sway_period_steps, sway_phase: period (control steps) and phase (rad, at step 0 after reset) of it.
        tau_s: first-order lag of the velocity after a steering change (s).
        delay_steps: pure delay of the response (control steps).
        startup_steps: control steps after reset before the legs move the body.
        control_hz: control rate of the measurement (Hz).
        circles: (k, 3) footprint circles (x, y, r) in the trunk frame (m).
        rays: (2, 4) ultrasonic rays (left, right): origin x, y and unit direction in the trunk frame.
        us_range: ultrasonic range (m).
        meta: how it was measured (command, version, seeds, steps, validation errors).
    """

    grid: np.ndarray
    velocity: np.ndarray
    sway: np.ndarray
    sway_period_steps: float
    sway_phase: float
    tau_s: float
    delay_steps: int
    startup_steps: int
    control_hz: float
    circles: np.ndarray
    rays: np.ndarray
    us_range: float
    meta: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        g = len(self.grid)
        if g < 2 or np.any(np.diff(self.grid) <= 0):
            raise ValueError("calibration grid must be increasing with at least 2 values")
        if self.velocity.shape != (g, g, 3):
            raise ValueError(f"calibration velocity must have shape ({g}, {g}, 3), got {self.velocity.shape}")
        if self.sway.shape != (g, g) or not self.sway_period_steps > 0:
            raise ValueError(f"calibration sway must have shape ({g}, {g}) and a period > 0")
        if self.tau_s < 0 or self.delay_steps < 0 or self.startup_steps < 0:
            raise ValueError("calibration lag, delay and startup must be >= 0")

    def scaled(self, speed: float = 1.0, turn: float = 1.0) -> Calibration:
        """A copy whose forward and lateral velocities are x ``speed`` and yaw rates x ``turn`` (a body that walks
        or turns faster or slower than the one measured; both > 0). Lag, delay, footprint and rays are kept."""
        if not (math.isfinite(speed) and speed > 0 and math.isfinite(turn) and turn > 0):
            raise ValueError(f"speed and turn factors must be finite and > 0, got {speed!r}, {turn!r}")
        velocity = self.velocity * np.array([speed, speed, turn])
        meta = {**self.meta, "scaled": {"speed": speed, "turn": turn}}
        return dataclasses.replace(self, velocity=velocity, meta=meta)

    def motion(self) -> np.ndarray:
        """The kernel's motion table (g, g, 4): forward, lateral, yaw rate, sway amplitude."""
        return np.concatenate([self.velocity, self.sway[:, :, None]], axis=2)

    def alpha(self) -> float:
        """Low-pass gain per control step for the lag ``tau_s``."""
        return 1.0 if self.tau_s <= 0 else 1.0 - math.exp(-1.0 / (self.control_hz * self.tau_s))

    def to_json(self) -> dict[str, Any]:
        """Plain-JSON form (what ``calibration.json`` holds)."""
        return {
            "grid": self.grid.tolist(),
            "velocity": self.velocity.tolist(),
            "velocity_units": ["m/s forward", "m/s left", "rad/s left"],
            "sway_rad": self.sway.tolist(),
            "sway_period_steps": self.sway_period_steps,
            "sway_phase_rad": self.sway_phase,
            "tau_s": self.tau_s,
            "delay_steps": self.delay_steps,
            "startup_steps": self.startup_steps,
            "control_hz": self.control_hz,
            "circles": self.circles.tolist(),
            "rays": self.rays.tolist(),
            "us_range": self.us_range,
            "meta": self.meta,
        }

    @classmethod
    def from_json(cls, d: dict[str, Any]) -> Calibration:
        """Inverse of :meth:`to_json`."""
        return cls(
            grid=np.asarray(d["grid"], float),
            velocity=np.asarray(d["velocity"], float),
            sway=np.asarray(d["sway_rad"], float),
            sway_period_steps=float(d["sway_period_steps"]),
            sway_phase=float(d["sway_phase_rad"]),
            tau_s=float(d["tau_s"]),
            delay_steps=int(d["delay_steps"]),
            startup_steps=int(d["startup_steps"]),
            control_hz=float(d["control_hz"]),
            circles=np.asarray(d["circles"], float).reshape(-1, 3),
            rays=np.asarray(d["rays"], float).reshape(2, 4),
            us_range=float(d["us_range"]),
            meta=dict(d.get("meta", {})),
        )


def load_calibration(path: str | Path | None = None, *, body: str = "surrogate") -> Calibration:
    """Read a calibration file (default: the one shipped in the package for planar ``body``, see
    :data:`CALIBRATION_FILES`); ValueError names an unreadable file or a body without one."""
    if path is None:
        if body not in CALIBRATION_FILES:
            known = ", ".join(CALIBRATION_FILES)
            raise ValueError(f"no calibration shipped for body {body!r}; expected one of {known}")
        return _shipped(body)
    p = Path(path)
    try:
        return Calibration.from_json(json.loads(p.read_text()))
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise ValueError(f"cannot read calibration file {p}: {e}") from e


@cache
def _shipped(body: str) -> Calibration:
    return load_calibration(CALIBRATION_FILES[body])


def box_rows(arena: ArenaSpec) -> np.ndarray:
    """The arena's boxes as kernel rows (m, 6): cx, cy, cos(yaw), sin(yaw), half x, half y."""
    rows = [(b.x, b.y, math.cos(b.yaw), math.sin(b.yaw), b.sx / 2, b.sy / 2) for b in arena.boxes]
    return np.asarray(rows, dtype=float).reshape(-1, 6)


@dataclass
class SurrogateRun:
    """Arrays of one surrogate run (:meth:`Surrogate.run`), row k after control step k.

    pose (T, 3), inputs (T, 2), outputs (T, 2), b (T, 2), q (T, 2) the network's weights (NaN with constant
    steering), us (T, 2) m, ``contacts`` the number of collision overlaps resolved.
    """

    pose: np.ndarray
    inputs: np.ndarray
    outputs: np.ndarray
    b: np.ndarray
    q: np.ndarray
    us: np.ndarray
    contacts: int = 0


NOISE_TAU = 0.05  # the ultrasonic noise's colour: low-pass gain per control step (as the physics body)

#: The columns of a run's rows a planar body fills (:class:`~neurowalk.body.world.CompiledWorld`).
PLANAR_COLUMNS: tuple[str, ...] = ("t", "pose", "inputs", "outputs", "b", "q", "us_distance")


class Surrogate:
    """One surrogate robot in an arena: a world (n = 1) stepped in compiled chunks of control steps with its network
    (:class:`~neurowalk.body.world.CompiledWorld`), or one step at a time (:class:`~neurowalk.body.world.World`).

    Args:
        arena: where it walks (boxes are walls; heights are ignored).
        calibration: the measured motion model (default: the file shipped for ``name``).
        noise: strength of the coloured ultrasonic noise (as the physics body).
        name: the registry name: ``surrogate`` (AMOSII's) or ``surrogate-wheeled``.

    Attributes:
        contacts: collision overlaps resolved since the last :meth:`reset`.
    """

    name = "surrogate"
    n = 1
    action = "steering"
    nq = 0
    qidx: None = None
    n_substeps = 1
    columns: tuple[str, ...] = PLANAR_COLUMNS

    def __init__(
        self,
        arena: ArenaSpec,
        calibration: Calibration | None = None,
        *,
        noise: float = 0.02,
        noise_tau: float = NOISE_TAU,
        name: str = "surrogate",
    ) -> None:
        if noise < 0 or not 0 < noise_tau <= 1:
            raise ValueError(f"noise needs strength >= 0 and 0 < tau <= 1, got {noise}, {noise_tau}")
        self.arena = arena
        self.name = name
        self.cal = cal = calibration or load_calibration(body=name)
        self.control_hz = cal.control_hz
        self.noise, self.noise_tau = noise, noise_tau
        self._boxes = box_rows(arena)
        self._motion = cal.motion()
        self._gain = math.sqrt(noise_tau) * noise
        self._rng: np.random.Generator | None = None
        self._state = np.zeros(kern.RUN_STATE)
        self._ring = np.zeros((cal.delay_steps + 1, self._motion.shape[2]))
        self._cmd = np.zeros(self._motion.shape[2])  # (one step at a time:) the command after the delay line
        self._omega, self._reach = 2.0 * math.pi / cal.sway_period_steps, kern.reach_of(cal.circles)
        self._seen, self._steer = np.zeros(2), np.zeros(2)
        self._pose = np.asarray(arena.start, dtype=float)
        self._k = 0
        self.contacts = 0

    def reset(self, rngs: Sequence[np.random.Generator]) -> None:
        """At the arena's start pose, at rest (the command delay line empty); the ultrasonic noise from ``rngs[0]``
        (drawn a chunk at a time: the same numbers in the same order as one draw for the whole run)."""
        self._rng = rngs[0]
        self._state[:] = 0.0
        self._state[kern.X], self._state[kern.Y], self._state[kern.YAW] = self.arena.start
        self._ring[:] = 0.0
        self._cmd[:] = 0.0
        self._k = 0
        self._pose[:] = self.arena.start
        self.contacts = 0

    def rollout(
        self,
        k0: int,
        k1: int,
        cols: dict[str, np.ndarray],
        base: int,
        network: tuple[np.ndarray, np.ndarray] | None,
        steer: np.ndarray | None,
    ) -> None:
        """Control steps ``k0 .. k1 - 1`` in one compiled call, after :meth:`reset` and the steps before ``k0``.

        Args:
            cols: the run's rows by column, each (1, rows, ...): row ``k - base`` of ``pose``, ``inputs``,
                ``outputs``, ``b``, ``q`` (not with constant steering) and ``us_distance`` is written after step k.
            network: the sensory network's (STATE_SIZE,) state (advanced in place) and packed params; or None with
            steer: a constant steering pair (O1, O2).
        """
        cal, rng = self.cal, self._rng
        assert rng is not None, "reset() first"
        if steer is not None:
            sens, p, fixed, steer = _NO_STATE, _NO_PARAMS, True, np.asarray(steer, dtype=float)
        elif network is not None:
            (sens, p), fixed, steer = network, False, _NO_STEER
        else:
            raise ValueError("a run of the surrogate needs its sensory network's arrays or a steering pair")
        self.contacts += kern.rollout(
            k0,
            k1,
            self._state,
            self._ring,
            sens,
            p,
            fixed,
            steer,
            self._boxes,
            cal.circles,
            cal.rays,
            cal.us_range,
            cal.grid,
            self._motion,
            cal.alpha(),
            cal.startup_steps,
            1.0 / cal.control_hz,
            cal.sway_period_steps,
            cal.sway_phase,
            rng.uniform(-1.0, 1.0, size=(k1 - k0, 2)),
            self._gain,
            self.noise_tau,
            cols["pose"][0],
            cols["inputs"][0],
            cols["outputs"][0],
            cols["b"][0],
            cols["q"][0],
            cols["us_distance"][0],
            base,
        )

    def warnings(self, i: int) -> dict[str, int]:
        """None: the planar body has no physics to warn."""
        return {}

    # -- one control step at a time (a :class:`~neurowalk.body.world.World` of one world), for a controller stepped
    # by its act() and for a Gymnasium agent: the kernels of rollout, the noise drawn a step at a time (the same
    # numbers in the same order), so that it gives rollout's run bit for bit --------------------------------------

    @property
    def qpos(self) -> np.ndarray:
        """(1, 0): the planar body has no positions beyond its pose."""
        return _NO_QPOS

    @property
    def time(self) -> np.ndarray:
        """(1,) the simulated time (s): control steps taken since the reset over the control rate."""
        return np.array([self._k / self.control_hz])

    @property
    def pose(self) -> np.ndarray:
        """(1, 3) the pose now (x m, y m, yaw rad; the gait's sway included)."""
        return self._pose[None]

    def sense(self) -> tuple[np.ndarray, np.ndarray]:
        """This step's noisy ultrasonic distances (1, 2) (m, inf: no echo) and foot contacts (1, 6) (none: 0)."""
        assert self._rng is not None, "reset() first"
        cal = self.cal
        noise = self._rng.uniform(-1.0, 1.0, size=2)
        kern.sense(self._k, self._state, self._boxes, cal.rays, cal.us_range, self._omega, cal.sway_phase, noise,
                   self._gain, self.noise_tau, self._seen)  # fmt: skip
        return self._seen[None].copy(), np.zeros((1, 6))

    def observation(self, i: int) -> Observation:
        """This step's reading (after :meth:`sense`): distances, pose and time."""
        return Observation(us_distance=self._seen.copy(), pose=self._pose.copy(), time=self._k / self.control_hz)

    def apply(self, actions: np.ndarray) -> None:
        """The steering pair (O1, O2) of the next step: row 0 of ``actions`` (1, 2)."""
        self._steer[:] = actions[0]

    def advance(self) -> None:
        """One control step of the calibrated motion with the steering applied."""
        cal = self.cal
        hits, yaw = kern.act(self._k, self._state, self._ring, float(self._steer[0]), float(self._steer[1]),
                             self._cmd, cal.grid, self._motion, cal.alpha(), cal.startup_steps, 1.0 / cal.control_hz,
                             self._omega, cal.sway_phase, cal.circles, self._boxes, self._reach)  # fmt: skip
        self._k += 1
        self.contacts += hits
        self._pose[:] = (self._state[kern.X], self._state[kern.Y], yaw)

    def run(
        self,
        steps: int,
        rng: np.random.Generator,
        sens_state: np.ndarray | None,
        sens_p: np.ndarray | None,
        steer: tuple[float, float] | None = None,
    ) -> SurrogateRun:
        """``steps`` control steps from the arena's start pose in one compiled call (:meth:`rollout`), the noise
        from ``rng``, steered by the sensory network's ``sens_state`` (advanced in place) and ``sens_p``, or by the
        constant pair ``steer``. A run with a controller and its recording is the loop's
        (:func:`neurowalk.sim.loop.run_worlds`)."""
        if steer is None and (sens_state is None or sens_p is None):
            raise ValueError("a run of the sensory network needs its state and params arrays (or a steer pair)")
        network = (sens_state, sens_p) if sens_state is not None and sens_p is not None else None
        cols = {k: np.full((1, steps, d), np.nan) for k, d in
                (("pose", 3), ("inputs", 2), ("outputs", 2), ("b", 2), ("q", 2), ("us_distance", 2))}  # fmt: skip
        self.reset([rng])
        self.rollout(0, steps, cols, 0, network, None if steer is None else np.asarray(steer, dtype=float))
        pose, inputs, outputs, b, q, us = (cols[k][0] for k in ("pose", "inputs", "outputs", "b", "q", "us_distance"))
        return SurrogateRun(pose, inputs, outputs, b, q, us, self.contacts)


_NO_STATE, _NO_PARAMS, _NO_STEER = np.zeros(STATE_SIZE), np.zeros(PARAMS_SIZE), np.zeros(2)
_NO_QPOS = np.empty((1, 0))


def steered_poses(cal: Calibration, arena: ArenaSpec, steps: int, steer: tuple[float, float]) -> np.ndarray:
    """Poses (steps, 3) (x m, y m, yaw rad) of a noiseless surrogate of calibration ``cal`` in ``arena``, steered
    with the fixed pair ``steer`` (O1, O2) from the arena's start pose: how calibration checks a fitted motion."""
    return Surrogate(arena, cal, noise=0.0).run(steps, np.random.default_rng(0), None, None, steer=steer).pose
