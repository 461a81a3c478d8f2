"""The fits of the surrogate's calibration: velocities, yaw sway and response lag from measured poses.

Pure functions of pose arrays (no MuJoCo): :mod:`.physics` measures the physics body and hands the poses here.
A pose row is (x m, y m, yaw rad) after one control step.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from neurowalk.body import surrogate_kernel as kern

HEADING_WEIGHT_M = 0.2  # m of position error that count as much as 1 rad of heading error in the lag fit
LAG_DELAYS: tuple[int, ...] = tuple(range(0, 61, 4))  # control steps: the lag fit's delays (AMOSII: the CPG's)
LAG_TAUS: tuple[float, ...] = (0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 15.0, 20.0)  # s: its time constants

StepRun = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""One step-change run as fitting material: pose at the switch (3,), velocity before (3,), commands (T, 3),
measured poses (T, 3)."""


def body_velocity(poses: np.ndarray, control_hz: float) -> np.ndarray:
    """Mean body-frame velocity (forward m/s, left m/s, yaw rate rad/s) over poses (T, 3) taken at ``control_hz``."""
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


def predict(
    pose0: np.ndarray, vel0: np.ndarray, commands: np.ndarray, delay: int, alpha: float, dt: float
) -> np.ndarray:
    """Poses (T, 3) of the surrogate's motion model from ``pose0`` and velocity ``vel0`` under commands (T, 3).

    ``delay``: control steps; ``alpha``: low-pass gain per step; ``dt``: control period (s).
    """
    state = np.zeros(kern.RUN_STATE)
    state[:3], state[3:6] = pose0, vel0
    ring = np.tile(vel0, (delay + 1, 1))
    out = np.empty((len(commands), 3))
    for k, c in enumerate(commands):
        kern.move(state, ring, k, c, alpha, dt)
        out[k] = state[:3]
    return out


def pose_error(pred: np.ndarray, meas: np.ndarray) -> float:
    """Mean pose error (m) of predicted against measured poses (T, 3): position + HEADING_WEIGHT_M x heading."""
    dp = np.linalg.norm(pred[:, :2] - meas[:, :2], axis=1)
    dh = np.abs(np.angle(np.exp(1j * (pred[:, 2] - meas[:, 2]))))
    return float(np.mean(dp + HEADING_WEIGHT_M * dh))


def fit_lag(
    runs: list[StepRun], hz: float, delays: Sequence[int] = LAG_DELAYS, taus: Sequence[float] = LAG_TAUS
) -> tuple[int, float, float]:
    """Best (delay steps, tau s, mean error m) over step-change runs, searched on the grid ``delays`` x ``taus``."""
    best = (0, 0.0, math.inf)
    for delay in delays:
        for tau in taus:
            alpha = 1.0 if tau == 0 else 1.0 - math.exp(-1.0 / (hz * tau))
            err = np.mean([pose_error(predict(p0, v0, c, delay, alpha, 1 / hz), m) for p0, v0, c, m in runs])
            if err < best[2]:
                best = (delay, tau, float(err))
    return best


def prune(circles: np.ndarray) -> np.ndarray:
    """Drop circles (x, y, r) that lie inside another one (k, 3) -> (k', 3); of equal circles the first stays."""
    keep = []
    for i, (x, y, r) in enumerate(circles):
        inside = any(
            j != i and math.hypot(x - cx, y - cy) + r <= cr + 1e-9 and (r < cr or j < i)
            for j, (cx, cy, cr) in enumerate(circles)
        )
        if not inside:
            keep.append((x, y, r))
    return np.asarray(keep)


def outline(a: float, b: float, r: float) -> np.ndarray:
    """Centres (k, 2) of circles of radius ``r`` (m) along the outline of a rectangle of half sides ``a`` x ``b``
    (m, about its centre, along its own axes): inset by ``r`` so that the circles reach its sides, at most ``r``
    apart, so that a side bulges in by no more than r(1 - cos 30°) = 0.13 r between two circles."""
    if not 0 < r <= min(a, b):
        raise ValueError(f"outline circle radius must be in (0, {min(a, b)}] m, got {r}")
    ia, ib = a - r, b - r
    xs = np.linspace(-ia, ia, max(1, math.ceil(2 * ia / r - 1e-9)) + 1)
    ys = np.linspace(-ib, ib, max(1, math.ceil(2 * ib / r - 1e-9)) + 1)
    pts = [(x, s * ib) for s in (-1.0, 1.0) for x in xs] + [(s * ia, y) for s in (-1.0, 1.0) for y in ys[1:-1]]
    return np.unique(np.asarray(pts), axis=0)
