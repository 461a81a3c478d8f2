"""Measure a physics body so that a planar surrogate can move like it (``neurowalk calibrate [--body NAME]``).

Two subjects (:data:`SUBJECTS`): AMOSII (for the body ``surrogate``) and the wheeled robot (``surrogate-wheeled``).
What is measured, on the MuJoCo body in the open arena with constant steering (O1, O2), fed to AMOSII through the
full locomotion network and to the wheeled robot directly (its ``apply`` takes the steering pair):

* steady body velocity (forward, lateral, yaw rate) over a grid of steering pairs, averaged over
  whole gait cycles after a warm-up;
* the yaw sway: AMOSII's trunk rocks with the gait (amplitude per pair, period and phase fitted); the wheeled
  robot has no gait, so its sway is 0 (the measured rocking is kept in the meta data);
* the response to step changes of the steering (forward -> turn, turn -> other turn, ...), fitted
  by a pure delay plus a first-order lag, and the start-up time after reset;
* the footprint (circles over the body's geoms at rest) and the ultrasonic rays (sites ``US_L``, ``US_R``);
* a validation on steering pairs between the grid points: the surrogate, driven like the physics
  robot, against fresh physics runs (errors relative to the full-scale speed and turning rate).

The result is a :class:`~neurowalk.body.surrogate.Calibration` written to a JSON file. The fits themselves are in
:mod:`neurowalk.experiments.calibration.fit`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

import neurowalk
from neurowalk.arenas import make_arena
from neurowalk.body import surrogate_kernel as kern
from neurowalk.body.registry import make_body
from neurowalk.body.surrogate import CALIBRATION_FILES, Calibration, Surrogate
from neurowalk.body.wheeled import CHASSIS_BODY
from neurowalk.experiments.calibration.fit import (
    LAG_DELAYS,
    LAG_TAUS,
    StepRun,
    body_velocity,
    fit_lag,
    outline,
    pose_error,
    predict,
    prune,
    sway_fit,
    yaw_sway,
)
from neurowalk.neural.motor import LocomotionNetwork

__all__ = [
    "GRID",
    "HELD_OUT",
    "SUBJECTS",
    "WARMUP",
    "WINDOW",
    "Subject",
    "body_velocity",
    "calibrate",
    "drive",
    "fit_lag",
    "geometry",
    "plot_calibration",
    "predict",
    "subject",
    "sway_fit",
    "validation",
]

GRID: tuple[float, ...] = (-1.0, -0.5, -0.3, -0.2, -0.1, 0.0, 0.1, 0.2, 0.3, 0.5, 1.0)
HELD_OUT: tuple[float, ...] = (-0.75, -0.4, -0.15, -0.05, 0.05, 0.15, 0.4, 0.75)
WARMUP = 300  # control steps before measuring (the CPG post-processing settles within ~90)
WINDOW = 612  # control steps measured: 7 gait cycles of 87.5 steps
STEPS_AFTER = 300  # control steps recorded after a step change
FORWARD = (-1.0, -1.0)  # steering of free walking: no obstacle -> inputs -1 -> outputs -1
STEP_CHANGES: tuple[tuple[tuple[float, float], tuple[float, float]], ...] = (
    (FORWARD, (-1.0, 1.0)),  # forward -> turn
    (FORWARD, (1.0, -1.0)),  # forward -> the other turn
    ((-1.0, 1.0), (1.0, -1.0)),  # one turn -> the other
    ((1.0, -1.0), FORWARD),  # turn -> forward
    ((0.0, 0.0), FORWARD),  # stop -> forward
    (FORWARD, (1.0, 1.0)),  # forward -> backward
)
CONTROL_HZ = 10.0  # Hz, the control rate the calibration is measured at


@dataclass(frozen=True)
class Subject:
    """A physics body that ``neurowalk calibrate`` measures (at its default options), and how.

    Attributes:
        body: its registry name. surrogate: the planar body it calibrates (whose data file it writes).
        chassis: the MJCF body whose frame is the pose (the surrogate's footprint and rays are in that frame).
        gait: steered through the locomotion network, its trunk rocking with the gait (the sway is fitted); else
            the steering pair goes to ``apply`` directly and the stored sway is 0.
        box_circle_m: None: a box is a chain of circles as wide as the box along its x axis (AMOSII's narrow
            trunk boxes); a number: the box's outline in circles of at most that radius (m; a wide chassis).
        delays, taus: the lag fit's grid (control steps, s). startup_stride: control steps between the start-up
            candidates. how: the method in words (for the file's meta data).
    """

    body: str
    surrogate: str
    chassis: str
    gait: bool
    box_circle_m: float | None
    delays: tuple[int, ...]
    taus: tuple[float, ...]
    startup_stride: int
    how: str


NO_SWAY_PERIOD = float(WINDOW)  # control steps: the stored period of a body without a gait (its amplitude is 0)
SUBJECTS: dict[str, Subject] = {
    "amosii": Subject(
        "amosii",
        "surrogate",
        "trunk",
        True,
        None,
        LAG_DELAYS,
        LAG_TAUS,
        5,
        "AMOSII (MuJoCo, open arena, no noise) driven by constant steering through the locomotion network; "
        f"velocity = mean body-frame velocity over {WINDOW} control steps (7 gait cycles) after {WARMUP} steps; "
        f"lag = delay + first-order lag fitted to {len(STEP_CHANGES)} step changes of the steering "
        f"({STEPS_AFTER} steps each; mean error {{lag:.3f}} m); start-up fitted on a forward run from reset; "
        "footprint and rays from the MJCF in the standing pose; yaw sway = sqrt(2) x std of the detrended yaw over "
        "the same window, its period and phase fitted on the forward run.",
    ),
    "wheeled": Subject(
        "wheeled",
        "surrogate-wheeled",
        CHASSIS_BODY,
        False,
        0.04,
        tuple(range(9)),
        (0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0),
        1,
        "the wheeled robot (MuJoCo, scale 1, open arena, no noise) driven by constant steering applied to its "
        f"wheels directly (no locomotion network); velocity = mean body-frame velocity over {WINDOW} control steps "
        f"after {WARMUP} steps; lag = delay + first-order lag fitted to {len(STEP_CHANGES)} step changes of the "
        f"steering ({STEPS_AFTER} steps each; mean error {{lag:.3f}} m); start-up fitted on a forward run from "
        "reset; footprint from the MJCF at rest (the chassis box's outline in circles of 4 cm, the wheels' in "
        "circles of their half width, the casters), rays from its US_L and US_R sites; no gait, so no yaw sway: "
        f"amplitude 0 (the largest measured, sqrt(2) x std of the detrended yaw, is in sway_measured_max_rad), "
        f"period {NO_SWAY_PERIOD:g} steps and phase 0 (unused).",
    ),
}


def subject(body: str) -> Subject:
    """The calibration subject of physics body ``body``; ValueError names a body that has none."""
    if body not in SUBJECTS:
        raise ValueError(f"cannot calibrate body {body!r}; expected one of {', '.join(SUBJECTS)}")
    return SUBJECTS[body]


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


def _drive_const(args: tuple[float, float, int, str]) -> np.ndarray:
    o1, o2, steps, body = args
    return drive(np.tile([o1, o2], (steps, 1)), body)


def steady_table(
    grid: Sequence[float], workers: int = 2, progress: bool = True, body: str = "amosii"
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Steady velocity (g, g, 3) and measured yaw sway amplitude (g, g) rad at ``grid`` pairs, and the forward
    run's poses (T, 3) (for the sway's period and phase)."""
    pairs = [(a, b) for a in grid for b in grid]
    poses = _map(_drive_const, [(a, b, WARMUP + WINDOW, body) for a, b in pairs], workers, progress, "steady")
    v = np.array([body_velocity(p[WARMUP:], CONTROL_HZ) for p in poses])
    sway = np.array([math.sqrt(2.0) * np.std(yaw_sway(p[WARMUP:])) for p in poses])
    g = len(grid)
    return v.reshape(g, g, 3), sway.reshape(g, g), poses[pairs.index(FORWARD)]


def _map(fn: Any, jobs: list[Any], workers: int, progress: bool, desc: str) -> list[Any]:
    """``[fn(j) for j in jobs]`` on the project's process pool, with a progress bar; the first error is raised."""
    from tqdm import tqdm

    from neurowalk.runners.local import run_unordered

    out: list[Any] = [None] * len(jobs)
    with tqdm(total=len(jobs), unit="run", desc=desc, disable=not progress, mininterval=0.5) as bar:
        for d in run_unordered(fn, jobs, workers=workers):
            if d.error is not None:
                raise d.error
            out[d.index] = d.value
            bar.update(1)
    return out


def step_runs(table_cal: Calibration, body: str = "amosii") -> list[StepRun]:
    """Physics step-change runs of ``body`` as fitting material: (pose at the switch, velocity before, commands,
    poses); the commands are the velocities ``table_cal``'s table gives."""
    runs = []
    hz = table_cal.control_hz
    for a, b in STEP_CHANGES:
        sched = np.vstack([np.tile(a, (WARMUP, 1)), np.tile(b, (STEPS_AFTER, 1))])
        poses = drive(sched, body)
        cmd = np.empty((STEPS_AFTER, 3))
        kern.velocity_command(table_cal.grid, table_cal.velocity, b[0], b[1], cmd[0])
        cmd[:] = cmd[0]
        v0 = np.zeros(3)
        kern.velocity_command(table_cal.grid, table_cal.velocity, a[0], a[1], v0)
        if a == (0.0, 0.0):
            v0 = body_velocity(poses[WARMUP - 100 : WARMUP], hz)
        runs.append((poses[WARMUP - 1], v0, cmd, poses[WARMUP:]))
    return runs


def fit_startup(cal: Calibration, body: str = "amosii") -> int:
    """Control steps after reset before the body moves, fitted on a forward run from reset."""
    meas = drive(np.tile(FORWARD, (WARMUP, 1)), body)
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


def surrogate_velocity(cal: Calibration, pairs: Sequence[tuple[float, float]]) -> np.ndarray:
    """Steady velocity (n, 3) of the surrogate at steering pairs, measured like the physics robot's."""
    out = []
    for a, b in pairs:
        run = Surrogate(make_arena("open"), cal, noise=0.0).run(
            WARMUP + WINDOW, np.random.default_rng(0), None, None, steer=(a, b)
        )
        out.append(body_velocity(run.pose[WARMUP:], cal.control_hz))
    return np.asarray(out)


def validation(
    cal: Calibration, held_out: Sequence[float], workers: int, progress: bool, body: str = "amosii"
) -> dict[str, Any]:
    """Surrogate against fresh runs of physics ``body`` at steering pairs between the grid points.

    Errors are relative to the full scale: the largest forward speed (m/s) and yaw rate (rad/s) over the grid.
    """
    pairs = [(a, b) for a in held_out for b in held_out]
    phys = np.array(
        [
            body_velocity(p[WARMUP:], CONTROL_HZ)
            for p in _map(
                _drive_const, [(a, b, WARMUP + WINDOW, body) for a, b in pairs], workers, progress, "validation"
            )
        ]
    )
    sur = surrogate_velocity(cal, pairs)
    speed = np.hypot(phys[:, 0], phys[:, 1]), np.hypot(sur[:, 0], sur[:, 1])
    full_v = float(np.max(np.hypot(cal.velocity[..., 0], cal.velocity[..., 1])))
    full_w = float(np.max(np.abs(cal.velocity[..., 2])))
    ev = np.abs(speed[1] - speed[0]) / full_v
    ew = np.abs(sur[:, 2] - phys[:, 2]) / full_w
    return {
        "pairs": [list(p) for p in pairs],
        "physics": phys.tolist(),
        "surrogate": sur.tolist(),
        "full_scale": {"speed_m_s": full_v, "yaw_rate_rad_s": full_w},
        "speed_error_max": float(ev.max()),
        "speed_error_mean": float(ev.mean()),
        "yaw_rate_error_max": float(ew.max()),
        "yaw_rate_error_mean": float(ew.mean()),
    }


def calibrate(
    grid: Sequence[float] = GRID,
    held_out: Sequence[float] = HELD_OUT,
    *,
    workers: int = 2,
    progress: bool = True,
    body: str = "amosii",
) -> Calibration:
    """Run every measurement on physics ``body`` (``amosii`` or ``wheeled``, see :data:`SUBJECTS`) and return the
    calibration of its surrogate (with its validation in ``meta``); ``grid`` must hold -1 (the forward run).

    Raises:
        ValueError: naming a body that cannot be calibrated, or a grid without -1.
    """
    sub = subject(body)
    if -1.0 not in grid:
        raise ValueError(f"the calibration grid must hold -1 (steering {FORWARD} walks forward), got {list(grid)}")
    t0 = time.perf_counter()
    circles, rays, us_range = geometry(body)
    g = np.asarray(grid, dtype=float)
    table, sway, forward = steady_table(g, workers, progress, body)
    extra: dict[str, Any] = {}
    if sub.gait:
        period, phase = sway_fit(yaw_sway(forward[WARMUP:]), WARMUP + 1)
    else:  # no gait: what rocking there is is not periodic, and the surrogate gets none
        extra["sway_measured_max_rad"] = float(sway.max())
        sway, period, phase = np.zeros_like(sway), NO_SWAY_PERIOD, 0.0
    motion = (g, table, sway, period, phase)
    cal = Calibration(*motion, 0.0, 0, 0, CONTROL_HZ, circles, rays, us_range)
    delay, tau, lag_err = fit_lag(step_runs(cal, body), CONTROL_HZ, sub.delays, sub.taus)
    cal = Calibration(*motion, tau, delay, 0, CONTROL_HZ, circles, rays, us_range)
    startup = fit_startup(cal, body)
    meta = {
        "command": "neurowalk calibrate" + ("" if body == "amosii" else f" --body {body}"),
        "neurowalk_version": neurowalk.__version__,
        "mujoco_version": mujoco.__version__,
        "how": sub.how.format(lag=lag_err),
        "warmup_steps": WARMUP,
        "window_steps": WINDOW,
        "step_changes": [list(map(list, sc)) for sc in STEP_CHANGES],
        "lag_fit_error_m": lag_err,
        **extra,
    }
    cal = Calibration(*motion, tau, delay, startup, CONTROL_HZ, circles, rays, us_range, meta)
    meta["validation"] = validation(cal, held_out, workers, progress, body)
    meta["body"], meta["surrogate"], meta["file"] = body, sub.surrogate, CALIBRATION_FILES[sub.surrogate].name
    meta["wall_time_s"] = time.perf_counter() - t0
    return cal


def plot_calibration(cal: Calibration) -> Any:
    """Figure: forward speed and yaw rate over the steering grid, and surrogate vs physics on held-out pairs."""
    from neurowalk.plotting import pyplot

    plt = pyplot()
    fig, ax = plt.subplots(1, 3, figsize=(13, 4))
    g = cal.grid
    panels = ((ax[0], 0, "forward speed (cm/s)", 100.0), (ax[1], 2, "yaw rate (deg/s)", 180 / math.pi))
    for a, k, label, scale in panels:
        im = a.imshow(cal.velocity[:, :, k].T * scale, origin="lower", cmap="coolwarm", aspect="auto")
        a.set_xticks(range(len(g)), [f"{v:g}" for v in g], fontsize=7)
        a.set_yticks(range(len(g)), [f"{v:g}" for v in g], fontsize=7)
        a.set_xlabel("O1")
        a.set_ylabel("O2")
        a.set_title(label)
        fig.colorbar(im, ax=a)
    v = cal.meta.get("validation")
    if v:
        phys, sur = np.asarray(v["physics"]), np.asarray(v["surrogate"])
        fs = v["full_scale"]
        ax[2].plot(phys[:, 0] / fs["speed_m_s"], sur[:, 0] / fs["speed_m_s"], "o", label="forward speed")
        ax[2].plot(
            phys[:, 2] / fs["yaw_rate_rad_s"], sur[:, 2] / fs["yaw_rate_rad_s"], "s", mfc="none", label="yaw rate"
        )
        ax[2].plot([-1, 1], [-1, 1], "k-", lw=0.8)
        ax[2].set_xlabel("physics (fraction of full scale)")
        ax[2].set_ylabel("surrogate")
        ax[2].set_title(f"held-out pairs: max error {max(v['speed_error_max'], v['yaw_rate_error_max']):.1%}")
        ax[2].legend(fontsize=8)
    name = cal.meta.get("surrogate", "surrogate")
    fig.suptitle(
        f"{name} calibration: lag {cal.tau_s:g} s + {cal.delay_steps} steps, start-up {cal.startup_steps} steps"
    )
    fig.tight_layout()
    return fig
