"""Measure the physics robot so that the planar surrogate can move like it (``neurowalk calibrate``).

What is measured, all on the MuJoCo AMOSII in the open arena with constant steering (O1, O2) fed to
the full locomotion network:

* steady body velocity (forward, lateral, yaw rate) over a grid of steering pairs, averaged over
  whole gait cycles after a warm-up;
* the response to step changes of the steering (forward -> turn, turn -> other turn, ...), fitted
  by a pure delay plus a first-order lag, and the start-up time after reset;
* the footprint (circles over trunk and leg geoms in the standing pose) and the ultrasonic rays;
* a validation on steering pairs between the grid points: the surrogate, driven like the physics
  robot, against fresh physics runs (errors relative to the full-scale speed and turning rate).

The result is a :class:`~neurowalk.body.surrogate.Calibration` written to a JSON file.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np

import neurowalk
from neurowalk.arenas import make_arena
from neurowalk.body import surrogate_kernel as kern
from neurowalk.body.amosii_params import BodyParams
from neurowalk.body.physics import AmosII
from neurowalk.body.surrogate import Calibration, Surrogate
from neurowalk.neural.motor import LocomotionNetwork

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
HEADING_WEIGHT_M = 0.2  # m of position error that count as much as 1 rad of heading error in the lag fit


def drive(schedule: np.ndarray, params: BodyParams | None = None) -> np.ndarray:
    """Physics robot in the open arena driven by steering ``schedule`` (T, 2); returns trunk poses (T, 3)."""
    body = AmosII(make_arena("open"), params, control_hz=CONTROL_HZ, noise=0.0)
    body.reset(np.random.default_rng(0))
    net = LocomotionNetwork()
    poses = np.empty((len(schedule), 3))
    for k, (o1, o2) in enumerate(schedule):
        body.observe()
        body.apply(net.step(float(o1), float(o2)))
        body.advance()
        poses[k] = body.observe().pose
    return poses


def _drive_const(args: tuple[float, float, int]) -> np.ndarray:
    o1, o2, steps = args
    return drive(np.tile([o1, o2], (steps, 1)))


def body_velocity(poses: np.ndarray, control_hz: float) -> np.ndarray:
    """Mean body-frame velocity (forward m/s, left m/s, yaw rate rad/s) over poses (T, 3)."""
    d = np.diff(poses[:, :2], axis=0)
    yaw = np.unwrap(poses[:, 2])
    mid = 0.5 * (yaw[1:] + yaw[:-1])
    fwd = d[:, 0] * np.cos(mid) + d[:, 1] * np.sin(mid)
    left = -d[:, 0] * np.sin(mid) + d[:, 1] * np.cos(mid)
    n = len(d)
    return np.array([fwd.sum(), left.sum(), yaw[-1] - yaw[0]]) * control_hz / n


def yaw_sway(poses: np.ndarray) -> np.ndarray:
    """Yaw (T,) about its straight-line trend (rad): the trunk's rocking with the gait."""
    yaw = np.unwrap(poses[:, 2])
    k = np.arange(len(yaw))
    return yaw - np.polyval(np.polyfit(k, yaw, 1), k)


def sway_fit(residual: np.ndarray, first_step: int) -> tuple[float, float]:
    """Period (steps) and phase (rad at step 0) of the sinusoid that best fits a yaw residual from ``first_step``."""
    k = first_step + np.arange(len(residual))
    best = (math.inf, 0.0, 0.0)
    for period in np.arange(80.0, 95.0, 0.05):
        basis = np.column_stack([np.sin(2 * np.pi * k / period), np.cos(2 * np.pi * k / period)])
        (a, b), *_ = np.linalg.lstsq(basis, residual, rcond=None)  # r ~ a sin + b cos = A sin(wk + phase)
        err = float(np.sum((basis @ (a, b) - residual) ** 2))
        if err < best[0]:
            best = (err, float(period), math.atan2(b, a))
    return best[1], float(np.angle(np.exp(1j * best[2])))


def steady_table(grid: Sequence[float], workers: int = 2, progress: bool = True) -> tuple[np.ndarray, np.ndarray,
                                                                                           float, float]:  # fmt: skip
    """Steady velocity (g, g, 3), sway amplitude (g, g) rad, sway period (steps) and phase at ``grid`` pairs."""
    pairs = [(a, b) for a in grid for b in grid]
    poses = _map(_drive_const, [(a, b, WARMUP + WINDOW) for a, b in pairs], workers, progress, "steady")
    v = np.array([body_velocity(p[WARMUP:], CONTROL_HZ) for p in poses])
    sway = np.array([math.sqrt(2.0) * np.std(yaw_sway(p[WARMUP:])) for p in poses])
    fwd = pairs.index(FORWARD)
    period, phase = sway_fit(yaw_sway(poses[fwd][WARMUP:]), WARMUP + 1)
    g = len(grid)
    return v.reshape(g, g, 3), sway.reshape(g, g), period, phase


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


def predict(pose0: np.ndarray, vel0: np.ndarray, commands: np.ndarray, delay: int, alpha: float,
            dt: float) -> np.ndarray:  # fmt: skip
    """Poses (T, 3) of the surrogate's motion model from ``pose0`` and velocity ``vel0`` under commands (T, 3)."""
    state = np.zeros(kern.RUN_STATE)
    state[:3], state[3:6] = pose0, vel0
    ring = np.tile(vel0, (delay + 1, 1))
    out = np.empty((len(commands), 3))
    for k, c in enumerate(commands):
        kern.move(state, ring, k, c, alpha, dt)
        out[k] = state[:3]
    return out


def _error(pred: np.ndarray, meas: np.ndarray) -> float:
    dp = np.linalg.norm(pred[:, :2] - meas[:, :2], axis=1)
    dh = np.abs(np.angle(np.exp(1j * (pred[:, 2] - meas[:, 2]))))
    return float(np.mean(dp + HEADING_WEIGHT_M * dh))


def fit_lag(runs: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]], hz: float) -> tuple[int, float, float]:
    """Best (delay steps, tau s, mean error m) over step-change runs (pose0, vel0, commands, measured poses)."""
    best = (0, 0.0, math.inf)
    for delay in range(0, 61, 4):
        for tau in (0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 15.0, 20.0):
            alpha = 1.0 if tau == 0 else 1.0 - math.exp(-1.0 / (hz * tau))
            err = np.mean([_error(predict(p0, v0, c, delay, alpha, 1 / hz), m) for p0, v0, c, m in runs])
            if err < best[2]:
                best = (delay, tau, float(err))
    return best


def step_runs(table_cal: Calibration) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """Physics step-change runs as fitting material: (pose at the switch, velocity before, commands, poses)."""
    runs = []
    hz = table_cal.control_hz
    for a, b in STEP_CHANGES:
        sched = np.vstack([np.tile(a, (WARMUP, 1)), np.tile(b, (STEPS_AFTER, 1))])
        poses = drive(sched)
        cmd = np.empty((STEPS_AFTER, 3))
        kern.velocity_command(table_cal.grid, table_cal.velocity, b[0], b[1], cmd[0])
        cmd[:] = cmd[0]
        v0 = np.zeros(3)
        kern.velocity_command(table_cal.grid, table_cal.velocity, a[0], a[1], v0)
        if a == (0.0, 0.0):
            v0 = body_velocity(poses[WARMUP - 100 : WARMUP], hz)
        runs.append((poses[WARMUP - 1], v0, cmd, poses[WARMUP:]))
    return runs


def fit_startup(cal: Calibration) -> int:
    """Control steps after reset before the body moves, fitted on a forward run from reset."""
    meas = drive(np.tile(FORWARD, (WARMUP, 1)))
    start = np.asarray(make_arena("open").start, dtype=float)
    cmd_full = np.empty(3)
    kern.velocity_command(cal.grid, cal.velocity, *FORWARD, cmd_full)
    best = (0, math.inf)
    for s in range(0, WARMUP // 2, 5):
        cmd = np.zeros((WARMUP, 3))
        cmd[s:] = cmd_full
        pred = predict(start, np.zeros(3), cmd, cal.delay_steps, cal.alpha(), 1 / cal.control_hz)
        err = _error(pred, meas)
        if err < best[1]:
            best = (s, err)
    return best[0]


def geometry(params: BodyParams | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """Footprint circles (k, 3), ultrasonic rays (2, 4) and range (m), from the MJCF in the standing pose.

    Capsules give a circle at each end, spheres one, boxes a chain of circles as wide as the box.
    """
    body = AmosII(make_arena("open"), params, control_hz=CONTROL_HZ, noise=0.0)
    body.reset(np.random.default_rng(0))
    m, d = body.model, body.data
    trunk = m.body("trunk").id
    rot, origin = d.xmat[trunk].reshape(3, 3), d.xpos[trunk]

    def local(p: np.ndarray) -> np.ndarray:
        return (rot.T @ (p - origin))[:2]

    circles = []
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
        elif kind == mujoco.mjtGeom.mjGEOM_BOX:
            r = size[1]
            for x in np.arange(-size[0] + r, size[0] - r + 1e-9, r):
                circles.append((*local(pos + x * axes[:, 0]), r))
    rays = []
    for name in ("US_L", "US_R"):
        s = m.site(name).id
        direction = rot.T @ d.site_xmat[s].reshape(3, 3)[:, 2]
        rays.append((*local(d.site_xpos[s]), *(direction[:2] / np.linalg.norm(direction[:2]))))
    return _prune(np.asarray(circles)), np.asarray(rays), float(body.params.us_range)


def _prune(circles: np.ndarray) -> np.ndarray:
    """Drop circles that lie inside another one (k, 3) -> (k', 3)."""
    keep = []
    for i, (x, y, r) in enumerate(circles):
        inside = any(
            j != i and math.hypot(x - cx, y - cy) + r <= cr + 1e-9 and (r < cr or j < i)
            for j, (cx, cy, cr) in enumerate(circles)
        )
        if not inside:
            keep.append((x, y, r))
    return np.asarray(keep)


def surrogate_velocity(cal: Calibration, pairs: Sequence[tuple[float, float]]) -> np.ndarray:
    """Steady velocity (n, 3) of the surrogate at steering pairs, measured like the physics robot's."""
    out = []
    for a, b in pairs:
        run = Surrogate(make_arena("open"), cal, noise=0.0).run(WARMUP + WINDOW, np.random.default_rng(0), None, None,
                                                                  steer=(a, b))  # fmt: skip
        out.append(body_velocity(run.pose[WARMUP:], cal.control_hz))
    return np.asarray(out)


def validation(cal: Calibration, held_out: Sequence[float], workers: int, progress: bool) -> dict[str, Any]:
    """Surrogate against fresh physics runs at steering pairs between the grid points.

    Errors are relative to the full scale: the largest forward speed and yaw rate over the grid.
    """
    pairs = [(a, b) for a in held_out for b in held_out]
    phys = np.array([body_velocity(p[WARMUP:], CONTROL_HZ) for p in _map(
        _drive_const, [(a, b, WARMUP + WINDOW) for a, b in pairs], workers, progress, "validation")])  # fmt: skip
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


def calibrate(grid: Sequence[float] = GRID, held_out: Sequence[float] = HELD_OUT, *, workers: int = 2,
              progress: bool = True) -> Calibration:  # fmt: skip
    """Run every measurement on the physics robot and return the calibration (with its validation in ``meta``)."""
    t0 = time.perf_counter()
    circles, rays, us_range = geometry()
    g = np.asarray(grid, dtype=float)
    table, sway, period, phase = steady_table(g, workers, progress)
    motion = (g, table, sway, period, phase)
    cal = Calibration(*motion, 0.0, 0, 0, CONTROL_HZ, circles, rays, us_range)
    delay, tau, lag_err = fit_lag(step_runs(cal), CONTROL_HZ)
    cal = Calibration(*motion, tau, delay, 0, CONTROL_HZ, circles, rays, us_range)
    startup = fit_startup(cal)
    meta = {
        "command": "neurowalk calibrate",
        "neurowalk_version": neurowalk.__version__,
        "mujoco_version": mujoco.__version__,
        "how": "AMOSII (MuJoCo, open arena, no noise) driven by constant steering through the locomotion network; "
        f"velocity = mean body-frame velocity over {WINDOW} control steps (7 gait cycles) after {WARMUP} steps; "
        f"lag = delay + first-order lag fitted to {len(STEP_CHANGES)} step changes of the steering "
        f"({STEPS_AFTER} steps each; mean error {lag_err:.3f} m); start-up fitted on a forward run from reset; "
        "footprint and rays from the MJCF in the standing pose; yaw sway = sqrt(2) x std of the detrended yaw over "
        "the same window, its period and phase fitted on the forward run.",
        "warmup_steps": WARMUP,
        "window_steps": WINDOW,
        "step_changes": [list(map(list, sc)) for sc in STEP_CHANGES],
        "lag_fit_error_m": lag_err,
    }
    cal = Calibration(*motion, tau, delay, startup, CONTROL_HZ, circles, rays, us_range, meta)
    meta["validation"] = validation(cal, held_out, workers, progress)
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
        ax[2].plot(phys[:, 2] / fs["yaw_rate_rad_s"], sur[:, 2] / fs["yaw_rate_rad_s"], "s", mfc="none",
                   label="yaw rate")  # fmt: skip
        ax[2].plot([-1, 1], [-1, 1], "k-", lw=0.8)
        ax[2].set_xlabel("physics (fraction of full scale)")
        ax[2].set_ylabel("surrogate")
        ax[2].set_title(f"held-out pairs: max error {max(v['speed_error_max'], v['yaw_rate_error_max']):.1%}")
        ax[2].legend(fontsize=8)
    fig.suptitle(f"surrogate calibration: lag {cal.tau_s:g} s + {cal.delay_steps} steps, "
                 f"start-up {cal.startup_steps} steps")  # fmt: skip
    fig.tight_layout()
    return fig
