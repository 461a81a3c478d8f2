"""What every MuJoCo body shares: the physics step fitted to the control rate, MuJoCo's warnings, and obstacle
contact replayed from recorded positions."""

from __future__ import annotations

import mujoco
import numpy as np

from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body.amosii_mjcf import BodyParams, amosii_xml, obstacle_contact


def n_substeps(control_hz: float, timestep: float) -> int:
    """Physics steps per control step: the whole number nearest ``1 / (control_hz * timestep)`` (at least 1).

    Where the control period is not a whole number of ``timestep`` steps (27 Hz at 0.01 s: 3.70 steps),
    :func:`set_control_rate` shortens or lengthens the physics step so that it is (4 steps of 9.26 ms).
    """
    if not control_hz > 0 or not timestep > 0:
        raise ValueError(f"control_hz and timestep must be > 0, got {control_hz!r}, {timestep!r}")
    return max(1, round(1.0 / (control_hz * timestep)))


def set_control_rate(model: mujoco.MjModel, control_hz: float) -> int:
    """Fit ``model``'s physics step to the control rate; returns the physics steps per control step.

    One control step is ``n`` physics steps of ``1 / (control_hz * n)`` s, ``n`` the whole number nearest the
    model's own step (:func:`n_substeps`): the model's timestep is kept where the period is a whole number of it
    (10 Hz at 0.01 s: 10 steps) and changed by at most half a step's worth where not (27 Hz: 4 steps of 9.26 ms
    instead of 10 ms), so the control period is exact at every rate.
    """
    n = n_substeps(control_hz, model.opt.timestep)
    dt = 1.0 / (control_hz * n)
    if abs(dt - model.opt.timestep) > 1e-12 * dt:
        model.opt.timestep = dt
    return n


def mujoco_warnings(data: mujoco.MjData) -> dict[str, int]:
    """MuJoCo warnings raised so far in ``data``, by name (empty when none)."""
    return {mujoco.mjtWarning(i).name: int(w.number) for i, w in enumerate(data.warning) if w.number}


def obstacle_contacts(
    arena: ArenaSpec, qpos: np.ndarray, rows: np.ndarray | None = None, params: BodyParams | None = None
) -> np.ndarray:
    """Per-step obstacle contact of a recorded run, replayed from its positions.

    Collision detection depends on positions only, so each asked row's ``qpos`` is put into a fresh model of
    ``arena`` (kinematics and collision, no dynamics) and :func:`~neurowalk.body.amosii_mjcf.obstacle_contact` read.

    Args:
        arena: the run's arena.
        qpos: (T, nq) recorded positions (``Trajectory.qpos``).
        rows: the row indices to replay (default: all).
        params: the body's parameters (default ``BodyParams()``, as every run uses).

    Returns:
        (T,) 1.0 where the trunk or a leg touched an obstacle, 0.0 where not, NaN for rows not replayed.
    """
    model = mujoco.MjModel.from_xml_string(amosii_xml(params or BodyParams(), world=arena.to_mjcf()))
    data = mujoco.MjData(model)
    if qpos.ndim != 2 or qpos.shape[1] != model.nq:
        raise ValueError(f"qpos must have shape (T, {model.nq}), got {qpos.shape}")
    out = np.full(len(qpos), np.nan)
    for k in np.arange(len(qpos)) if rows is None else np.asarray(rows, dtype=int):
        data.qpos[:] = qpos[k]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_collision(model, data)
        out[k] = float(obstacle_contact(model, data))
    return out
