"""Measure a physics body so that a planar surrogate can move like it (``neurowalk calibrate [--body NAME]``).

Two subjects (:data:`~.subjects.SUBJECTS`): AMOSII (for the body ``surrogate``) and the wheeled robot
(``surrogate-wheeled``). What is measured, on the MuJoCo body in the open arena with constant steering (O1, O2), fed
to AMOSII through the full locomotion network and to the wheeled robot directly (its ``apply`` takes the steering
pair):

* steady body velocity (forward, lateral, yaw rate) over a grid of steering pairs, averaged over
  whole gait cycles after a warm-up;
* the yaw sway: AMOSII's trunk rocks with the gait (amplitude per pair, period and phase fitted); the wheeled
  robot has no gait, so its sway is 0 (the measured rocking is kept in the meta data);
* the response to step changes of the steering (forward -> turn, turn -> other turn, ...), fitted
  by a pure delay plus a first-order lag, and the start-up time after reset;
* the footprint (circles over the body's geoms at rest) and the ultrasonic rays (sites ``US_L``, ``US_R``).

The fits themselves are in :mod:`.fit`; :mod:`.calibrate` puts the measurements together into a
:class:`~neurowalk.body.surrogate.Calibration` and validates it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from neurowalk.arenas import make_arena
from neurowalk.body import surrogate_kernel as kern
from neurowalk.body.registry import make_body, physics_settings
from neurowalk.body.surrogate import Calibration
from neurowalk.experiments.calibration.fit import (
    StepRun,
    body_velocity,
    outline,
    pose_error,
    predict,
    prune,
    yaw_sway,
)
from neurowalk.experiments.calibration.subjects import (
    CONTROL_HZ,
    FORWARD,
    STEP_CHANGES,
    STEPS_AFTER,
    WARMUP,
    WINDOW,
    subject,
)
from neurowalk.experiments.study_runs import run_jobs
from neurowalk.neural.motor import LocomotionNetwork
from neurowalk.runners.sweep import job_kind

#: The runner's kind of a calibration drive: {"body": NAME, "phases": [[O1, O2, steps], ...], "physics": ...}.
DRIVE = job_kind("calibration-drive")


def _robot(body: str) -> Any:
    """Physics body ``body`` (default options, no noise) at rest at the open arena's start."""
    robot = make_body(subject(body).body, make_arena("open"), {}, control_hz=CONTROL_HZ, noise=0.0)
    robot.reset(np.random.default_rng(0))
    return robot


def drive(schedule: np.ndarray, body: str = "amosii") -> np.ndarray:
    """Physics body in the open arena driven by steering ``schedule`` (T, 2); returns its poses (T, 3): x m,
    y m, yaw rad of the subject's chassis frame after each control step."""
    robot = _robot(body)
    net = LocomotionNetwork() if subject(body).gait else None
    poses = np.empty((len(schedule), 3))
    for k, (o1, o2) in enumerate(schedule):
        robot.observe()
        robot.apply(net.step(float(o1), float(o2)) if net is not None else np.array([o1, o2], dtype=float))
        robot.advance()
        poses[k] = robot.observe().pose
    return poses


def drive_job(spec: dict[str, Any]) -> dict[str, Any]:
    """A :func:`drive` as the runner's job (:data:`DRIVE`): steering ``spec["phases"]`` ([O1, O2, steps] each, one
    after the other) on physics body ``spec["body"]``; ``{"poses": (T, 3) as lists}``."""
    schedule = np.vstack([np.tile([o1, o2], (int(n), 1)) for o1, o2, n in spec["phases"]])
    return {"poses": drive(schedule, spec["body"]).tolist()}


@dataclass(frozen=True)
class Drives:
    """How a calibration's drives run: on physics ``body``, through the one runner (``workers`` processes, a progress
    bar where ``progress``), kept in the result store of ``folder`` (None: a temporary one), so that a stopped
    calibration goes on from the drives it finished."""

    body: str = "amosii"
    workers: int = 2
    progress: bool = True
    folder: Path | None = None

    def poses(self, runs: Sequence[Sequence[tuple[float, float, int]]], desc: str) -> list[np.ndarray]:
        """Each run's poses (T, 3) (:func:`drive`; a run: its phases, (O1, O2, steps) each); ``desc`` names the
        progress bar. A drive's key holds the body's physics settings: drives of another physics run again."""
        physics = physics_settings(subject(self.body).body, {}, CONTROL_HZ)
        specs = [
            {"body": self.body, "phases": [[float(a), float(b), int(n)] for a, b, n in run], "physics": physics}
            for run in runs
        ]
        done = run_jobs(drive_job, specs, DRIVE, folder=self.folder, workers=self.workers, progress=self.progress,
                        desc=desc)  # fmt: skip
        return [np.asarray(d["poses"], dtype=float) for d in done]


def steady_table(grid: Sequence[float], drives: Drives) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Steady velocity (g, g, 3) and measured yaw sway amplitude (g, g) rad at ``grid`` pairs, and the forward
    run's poses (T, 3) (for the sway's period and phase)."""
    pairs = [(a, b) for a in grid for b in grid]
    poses = steady_poses(pairs, drives, "steady")
    v = np.array([body_velocity(p[WARMUP:], CONTROL_HZ) for p in poses])
    sway = np.array([math.sqrt(2.0) * np.std(yaw_sway(p[WARMUP:])) for p in poses])
    g = len(grid)
    return v.reshape(g, g, 3), sway.reshape(g, g), poses[pairs.index(FORWARD)]


def steady_poses(pairs: Sequence[tuple[float, float]], drives: Drives, desc: str) -> list[np.ndarray]:
    """Poses (WARMUP + WINDOW, 3) of the physics body driven at each constant steering pair of ``pairs`` (``desc``
    names the progress bar)."""
    return drives.poses([[(a, b, WARMUP + WINDOW)] for a, b in pairs], desc)


def step_runs(table_cal: Calibration, drives: Drives) -> list[StepRun]:
    """Physics step-change runs as fitting material: (pose at the switch, velocity before, commands, poses); the
    commands are the velocities ``table_cal``'s table gives."""
    runs = []
    hz = table_cal.control_hz
    phases = [[(*a, WARMUP), (*b, STEPS_AFTER)] for a, b in STEP_CHANGES]
    for (a, b), poses in zip(STEP_CHANGES, drives.poses(phases, "step changes"), strict=True):
        cmd = np.empty((STEPS_AFTER, 3))
        kern.velocity_command(table_cal.grid, table_cal.velocity, b[0], b[1], cmd[0])
        cmd[:] = cmd[0]
        v0 = np.zeros(3)
        kern.velocity_command(table_cal.grid, table_cal.velocity, a[0], a[1], v0)
        if a == (0.0, 0.0):
            v0 = body_velocity(poses[WARMUP - 100 : WARMUP], hz)
        runs.append((poses[WARMUP - 1], v0, cmd, poses[WARMUP:]))
    return runs


def fit_startup(cal: Calibration, drives: Drives) -> int:
    """Control steps after reset before the body moves, fitted on a forward run from reset."""
    body = drives.body
    (meas,) = drives.poses([[(*FORWARD, WARMUP)]], "start-up")
    start = np.asarray(make_arena("open").start, dtype=float)
    cmd_full = np.empty(3)
    kern.velocity_command(cal.grid, cal.velocity, *FORWARD, cmd_full)
    best = (0, math.inf)
    for s in range(0, WARMUP // 2, subject(body).startup_stride):
        cmd = np.zeros((WARMUP, 3))
        cmd[s:] = cmd_full
        pred = predict(start, np.zeros(3), cmd, cal.delay_steps, cal.alpha(), 1 / cal.control_hz)
        err = pose_error(pred, meas)
        if err < best[1]:
            best = (s, err)
    return best[0]


def geometry(body: str = "amosii") -> tuple[np.ndarray, np.ndarray, float]:
    """Footprint circles (k, 3) x, y, r m, ultrasonic rays (2, 4) origin x, y m and unit direction, and range (m),
    in the chassis frame, from the MJCF of physics ``body`` at rest (AMOSII: the standing pose).

    Capsules give a circle at each end, spheres one, boxes a chain of circles as wide as the box or their outline
    in circles (see :class:`Subject`), cylinders on their side (wheels) the outline of their footprint, upright
    ones a circle.
    """
    sub = subject(body)
    robot = _robot(body)
    m, d = robot.model, robot.data
    trunk = m.body(sub.chassis).id
    rot, origin = d.xmat[trunk].reshape(3, 3), d.xpos[trunk]

    def local(p: np.ndarray) -> np.ndarray:
        return (rot.T @ (p - origin))[:2]

    def rectangle(pos: np.ndarray, u: np.ndarray, v: np.ndarray, a: float, b: float, r: float) -> list[tuple]:
        return [(*local(pos + x * u + y * v), min(r, a, b)) for x, y in outline(a, b, min(r, a, b))]

    circles: list[tuple] = []
    for g in range(m.ngeom):
        if m.geom_bodyid[g] == 0:
            continue
        size, pos, axes = m.geom_size[g], d.geom_xpos[g], d.geom_xmat[g].reshape(3, 3)
        kind = m.geom_type[g]
        if kind == mujoco.mjtGeom.mjGEOM_CAPSULE:
            for sign in (-1.0, 1.0):
                circles.append((*local(pos + sign * size[1] * axes[:, 2]), size[0]))
        elif kind == mujoco.mjtGeom.mjGEOM_SPHERE:
            circles.append((*local(pos), size[0]))
        elif kind == mujoco.mjtGeom.mjGEOM_BOX and sub.box_circle_m is None:
            r = size[1]
            for x in np.arange(-size[0] + r, size[0] - r + 1e-9, r):
                circles.append((*local(pos + x * axes[:, 0]), r))
        elif kind == mujoco.mjtGeom.mjGEOM_BOX:
            circles += rectangle(pos, axes[:, 0], axes[:, 1], size[0], size[1], sub.box_circle_m)
        elif kind == mujoco.mjtGeom.mjGEOM_CYLINDER and abs(axes[2, 2]) > 0.5:  # upright: a disc
            circles.append((*local(pos), size[0]))
        elif kind == mujoco.mjtGeom.mjGEOM_CYLINDER:  # on its side: a rectangle, the axis one of its sides
            across = np.cross([0.0, 0.0, 1.0], axes[:, 2])
            circles += rectangle(pos, axes[:, 2], across / np.linalg.norm(across), size[1], size[0], size[1])
    rays = []
    for name in ("US_L", "US_R"):
        s = m.site(name).id
        direction = rot.T @ d.site_xmat[s].reshape(3, 3)[:, 2]
        rays.append((*local(d.site_xpos[s]), *(direction[:2] / np.linalg.norm(direction[:2]))))
    us_range = float(robot.params.us_range) * float(getattr(robot.params, "scale", 1.0))
    return prune(np.asarray(circles)), np.asarray(rays), us_range
