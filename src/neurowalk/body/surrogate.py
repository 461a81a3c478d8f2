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
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body import surrogate_kernel as kern
from neurowalk.neural.sensory import PARAMS_SIZE, STATE_SIZE

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
    """Arrays of one surrogate run, row k after control step k (see :class:`~neurowalk.sim.trajectory.Trajectory`).

    pose (T, 3), inputs (T, 2), outputs (T, 2), weights (T, 4) b1 b2 q1 q2, us (T, 2) m, ``contacts`` the
    number of collision overlaps resolved.
    """

    pose: np.ndarray
    inputs: np.ndarray
    outputs: np.ndarray
    weights: np.ndarray
    us: np.ndarray
    contacts: int = 0
    done: int = 0


def empty_run(steps: int) -> SurrogateRun:
    """NaN-filled arrays for ``steps`` rows."""
    pose, inputs, outputs, weights, us = (np.full((steps, n), np.nan) for n in (3, 2, 2, 4, 2))
    return SurrogateRun(pose, inputs, outputs, weights, us)


NOISE_TAU = 0.05  # the ultrasonic noise's colour: low-pass gain per control step (as the physics body)


class Surrogate:
    """One surrogate robot in an arena, stepped in compiled chunks.

    Args:
        arena: where it walks (boxes are walls; heights are ignored).
        calibration: the measured motion model (default: the file shipped for ``name``).
        noise: strength of the coloured ultrasonic noise (as the physics body).
        name: the registry name: ``surrogate`` (AMOSII's) or ``surrogate-wheeled``.
    """

    name = "surrogate"

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
        self.cal = calibration or load_calibration(body=name)
        self.control_hz = self.cal.control_hz
        self.noise, self.noise_tau = noise, noise_tau
        self._boxes = box_rows(arena)

    def run(
        self,
        steps: int,
        rng: np.random.Generator,
        sens_state: np.ndarray | None,
        sens_p: np.ndarray | None,
        steer: tuple[float, float] | None = None,
        chunk: int | None = None,
        on_chunk: Any = None,
        out: SurrogateRun | None = None,
        stream: bool = False,
    ) -> SurrogateRun:
        """Run ``steps`` control steps from the arena's start pose.

        Args:
            steps: control steps.
            rng: the body's Generator (ultrasonic noise, drawn a chunk at a time: the same numbers in the same
                order as one draw for the whole run).
            sens_state, sens_p: the sensory network's (STATE_SIZE,) state (advanced in place) and params array;
                ``None`` with ``steer`` for constant steering.
            steer: constant (O1, O2) instead of the network.
            chunk, on_chunk: if given, ``on_chunk(stop)`` is called after every ``chunk`` steps.
            out: arrays to write into (default: new ones, see :func:`empty_run`).
            stream: ``out`` holds one chunk (``chunk`` rows): the rows of steps [stop - n, stop) are its first n
                rows when ``on_chunk(stop)`` is called; memory does not grow with ``steps``.

        A KeyboardInterrupt stops the run between chunks; ``done`` tells how many rows are complete and were
        handed to ``on_chunk`` (a chunk whose ``on_chunk`` was interrupted does not count).
        """
        cal = self.cal
        fixed = steer is not None
        if fixed:
            sens_state, sens_p = np.zeros(STATE_SIZE), np.zeros(PARAMS_SIZE)
        elif sens_state is None or sens_p is None:
            raise ValueError("a run of the sensory network needs its state and params arrays (or a steer pair)")
        state = np.zeros(kern.RUN_STATE)
        state[kern.X], state[kern.Y], state[kern.YAW] = self.arena.start
        motion = cal.motion()
        gain = math.sqrt(self.noise_tau) * self.noise
        ring = np.zeros((cal.delay_steps + 1, motion.shape[2]))
        size = chunk or steps
        out = out if out is not None else empty_run(size if stream else steps)
        st = np.asarray(steer if fixed else (0.0, 0.0), dtype=float)
        try:
            for k0 in range(0, steps, size):
                k1 = min(steps, k0 + size)
                noise_u = rng.uniform(-1.0, 1.0, size=(k1 - k0, 2))
                out.contacts += kern.rollout(
                    k0,
                    k1,
                    state,
                    ring,
                    sens_state,
                    sens_p,
                    fixed,
                    st,
                    self._boxes,
                    cal.circles,
                    cal.rays,
                    cal.us_range,
                    cal.grid,
                    motion,
                    cal.alpha(),
                    cal.startup_steps,
                    1.0 / cal.control_hz,
                    cal.sway_period_steps,
                    cal.sway_phase,
                    noise_u,
                    gain,
                    self.noise_tau,
                    out.pose,
                    out.inputs,
                    out.outputs,
                    out.weights,
                    out.us,
                    k0 if stream else 0,
                )
                if on_chunk is not None:
                    on_chunk(k1)
                out.done = k1
        except KeyboardInterrupt:
            pass
        return out


def steered_poses(cal: Calibration, arena: ArenaSpec, steps: int, steer: tuple[float, float]) -> np.ndarray:
    """Poses (steps, 3) (x m, y m, yaw rad) of a noiseless surrogate of calibration ``cal`` in ``arena``, steered
    with the fixed pair ``steer`` (O1, O2) from the arena's start pose: how calibration checks a fitted motion."""
    return Surrogate(arena, cal, noise=0.0).run(steps, np.random.default_rng(0), None, None, steer=steer).pose


class Walker:
    """The surrogate stepped one control step at a time from Python, steered from outside (e.g. a Gymnasium agent).

    :meth:`sense` gives the readings at the current step (drawing the sensor noise from ``rng``), :meth:`act`
    takes the step with a steering pair. Sensing, then acting with the steering that :meth:`Surrogate.run` would
    hold constant, gives that run's trajectory bit for bit (the same kernel, the same noise draws in order).

    Args:
        body: the surrogate in its arena.
        rng: the body's Generator (ultrasonic noise).
    """

    def __init__(self, body: Surrogate, rng: np.random.Generator) -> None:
        cal = body.cal
        self.body, self.rng, self.cal = body, rng, cal
        self.state = np.zeros(kern.RUN_STATE)
        self.state[kern.X], self.state[kern.Y], self.state[kern.YAW] = body.arena.start
        self.motion = cal.motion()
        self.ring = np.zeros((cal.delay_steps + 1, self.motion.shape[2]))
        self.cmd = np.zeros(self.motion.shape[2])
        self.seen = np.zeros(2)
        self.gain = math.sqrt(body.noise_tau) * body.noise
        self.omega = 2.0 * math.pi / cal.sway_period_steps
        self.reach = kern.reach_of(cal.circles)
        self.alpha, self.dt = cal.alpha(), 1.0 / cal.control_hz
        self.k = 0  # control steps taken
        self.contacts = 0  # collision overlaps resolved so far
        self.pose = np.asarray(body.arena.start, dtype=float)  # (3,) x m, y m, yaw rad (sway included)

    def sense(self) -> np.ndarray:
        """(2,) ultrasonic distances (left, right) at the current step, m, ``inf`` = no echo; call once a step."""
        noise = self.rng.uniform(-1.0, 1.0, size=2)
        kern.sense(
            self.k,
            self.state,
            self.body._boxes,
            self.cal.rays,
            self.cal.us_range,
            self.omega,
            self.cal.sway_phase,
            noise,
            self.gain,
            self.body.noise_tau,
            self.seen,
        )
        return self.seen.copy()

    def act(self, o1: float, o2: float) -> np.ndarray:
        """Take one control step with steering (o1, o2) in [-1, 1]; return the pose after it (3,)."""
        n, yaw = kern.act(
            self.k,
            self.state,
            self.ring,
            float(o1),
            float(o2),
            self.cmd,
            self.cal.grid,
            self.motion,
            self.alpha,
            self.cal.startup_steps,
            self.dt,
            self.omega,
            self.cal.sway_phase,
            self.cal.circles,
            self.body._boxes,
            self.reach,
        )
        self.k += 1
        self.contacts += n
        self.pose = np.array([self.state[kern.X], self.state[kern.Y], yaw])
        return self.pose.copy()
