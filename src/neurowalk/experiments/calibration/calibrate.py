"""``neurowalk calibrate``: the calibration of a planar surrogate from its physics body's measurements
(:mod:`.physics`, :mod:`.fit`), validated on steering pairs between the grid points (the surrogate, driven like the
physics robot, against fresh physics runs; errors relative to the full-scale speed and turning rate), and its
picture.

The result is a :class:`~neurowalk.body.surrogate.Calibration` written to a JSON file.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

import neurowalk
from neurowalk.arenas import make_arena
from neurowalk.body.surrogate import CALIBRATION_FILES, Calibration, steered_poses
from neurowalk.experiments.calibration.fit import body_velocity, fit_lag, sway_fit, yaw_sway
from neurowalk.experiments.calibration.physics import (
    Drives,
    fit_startup,
    geometry,
    steady_poses,
    steady_table,
    step_runs,
)
from neurowalk.experiments.calibration.subjects import (
    CONTROL_HZ,
    DEFAULT_SUBJECT,
    FORWARD,
    GRID,
    HELD_OUT,
    NO_SWAY_PERIOD,
    STEP_CHANGES,
    WARMUP,
    WINDOW,
    subject,
)
from neurowalk.plotting import pyplot, styled


def surrogate_velocity(cal: Calibration, pairs: Sequence[tuple[float, float]]) -> np.ndarray:
    """Steady velocity (n, 3) of the surrogate at steering pairs, measured like the physics robot's."""
    out = []
    for a, b in pairs:
        pose = steered_poses(cal, make_arena("open"), WARMUP + WINDOW, (a, b))
        out.append(body_velocity(pose[WARMUP:], cal.control_hz))
    return np.asarray(out)


def held_pairs(held_out: Sequence[float]) -> list[tuple[float, float]]:
    """The steering pairs of a validation: every (O1, O2) of ``held_out`` values (between the grid points)."""
    return [(a, b) for a in held_out for b in held_out]


def validation(cal: Calibration, pairs: Sequence[tuple[float, float]], physics: np.ndarray) -> dict[str, Any]:
    """Surrogate against the physics body at steering ``pairs`` (:func:`held_pairs`): its steady velocity against
    ``physics`` (n, 3), the physics body's steady velocity (forward m/s, lateral m/s, yaw rad/s) at each pair.

    Errors are relative to the full scale: the largest forward speed (m/s) and yaw rate (rad/s) over the grid.
    """
    phys = np.asarray(physics, dtype=float)
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
    body: str = DEFAULT_SUBJECT,
    folder: Path | None = None,
) -> Calibration:
    """Run every measurement on physics ``body`` (``amosii`` or ``wheeled``, see :data:`SUBJECTS`) and return the
    calibration of its surrogate (with its validation in ``meta``); ``grid`` must hold -1 (the forward run).

    The drives run through the one runner (``workers`` processes), kept in the result store of ``folder`` (None: a
    temporary one): stopped, the same call goes on from the drives it finished.

    Raises:
        ValueError: naming a body that cannot be calibrated, or a grid without -1.
    """
    sub = subject(body)
    if -1.0 not in grid:
        raise ValueError(f"the calibration grid must hold -1 (steering {FORWARD} walks forward), got {list(grid)}")
    t0 = time.perf_counter()
    drives = Drives(body, workers, progress, folder)
    circles, rays, us_range = geometry(body)
    g = np.asarray(grid, dtype=float)
    table, sway, forward = steady_table(g, drives)
    extra: dict[str, Any] = {}
    if sub.gait:
        period, phase = sway_fit(yaw_sway(forward[WARMUP:]), WARMUP + 1)
    else:  # no gait: what rocking there is is not periodic, and the surrogate gets none
        extra["sway_measured_max_rad"] = float(sway.max())
        sway, period, phase = np.zeros_like(sway), NO_SWAY_PERIOD, 0.0
    motion = (g, table, sway, period, phase)
    cal = Calibration(*motion, 0.0, 0, 0, CONTROL_HZ, circles, rays, us_range)
    delay, tau, lag_err = fit_lag(step_runs(cal, drives), CONTROL_HZ, sub.delays, sub.taus)
    cal = Calibration(*motion, tau, delay, 0, CONTROL_HZ, circles, rays, us_range)
    startup = fit_startup(cal, drives)
    meta = {
        "command": "neurowalk calibrate" + ("" if body == DEFAULT_SUBJECT else f" --body {body}"),
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
    pairs = held_pairs(held_out)
    held = [body_velocity(p[WARMUP:], CONTROL_HZ) for p in steady_poses(pairs, drives, "validation")]
    meta["validation"] = validation(cal, pairs, np.array(held))
    meta["body"], meta["surrogate"], meta["file"] = body, sub.surrogate, CALIBRATION_FILES[sub.surrogate].name
    meta["wall_time_s"] = time.perf_counter() - t0
    return cal


@styled
def plot_calibration(cal: Calibration) -> Any:
    """Figure: forward speed and yaw rate over the steering grid, and surrogate vs physics on held-out pairs."""
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
