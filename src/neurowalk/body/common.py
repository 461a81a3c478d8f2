"""What every MuJoCo body and every engine shares: the start pose on the free joint, the noisy ultrasonic reading.

Each is written once here; the single bodies (:class:`~neurowalk.body.amosii.AmosII`, the wheeled robot), the
lock-step engines (:mod:`neurowalk.sim.batch`, :mod:`neurowalk.sim.warp_engine`) and the Gymnasium physics
kernel (:mod:`neurowalk.envs.vector_kernel`) call these, so a change of the sensor model reaches them all.

The ultrasonic reading (the authors' sensor model): a raw distance ``raw`` (m; ``inf`` or beyond the range: no
echo) becomes the activation ``u = max(0, 1 - raw / us_range)``, coloured noise is added, and the noisy
activation is turned back into a distance ``us_range * (1 - u)`` (``inf`` when ``u <= 0``: no echo).
"""

from __future__ import annotations

import math

import numpy as np

from neurowalk.compiled import jit

__all__ = ["noisy_distance", "noisy_distances", "place_at_start"]


@jit
def noisy_distance(raw: float, us_range: float, noise: float) -> float:
    """One noisy ultrasonic distance (m, ``inf``: no echo) from a raw one (m, ``inf``: none) and its noise sample."""
    u = 1.0 - raw / us_range
    if u < 0.0:
        u = 0.0
    u = u + noise
    return us_range * (1.0 - u) if u > 0.0 else math.inf


@jit
def _noisy_flat(raw: np.ndarray, us_range: float, noise: np.ndarray, out: np.ndarray) -> None:
    for i in range(raw.shape[0]):
        out[i] = noisy_distance(raw[i], us_range, noise[i])


def noisy_distances(raw: np.ndarray, us_range: float, noise: np.ndarray) -> np.ndarray:
    """:func:`noisy_distance` of every element: ``raw`` and ``noise`` of one shape, e.g. (2,) or (n, 2); a new array."""
    raw = np.ascontiguousarray(raw, dtype=np.float64)
    out = np.empty(raw.shape)
    _noisy_flat(
        raw.reshape(-1), float(us_range), np.ascontiguousarray(noise, dtype=np.float64).reshape(-1), out.reshape(-1)
    )
    return out


def place_at_start(qpos: np.ndarray, start: tuple[float, float, float]) -> None:
    """Put a free joint (``qpos[0:7]``: x, y, z, quaternion w, x, y, z) at an arena's start pose (x m, y m, yaw rad);
    the height is left as it is."""
    x, y, yaw = start
    qpos[0], qpos[1] = x, y
    qpos[3:7] = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
