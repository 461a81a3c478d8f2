"""Compiled step of N surrogate copies at once (``neurowalk/Explore-v0`` vectorised): motion, coverage, sensing.

Each copy runs the surrogate's own :func:`~neurowalk.body.surrogate_kernel.act` and
:func:`~neurowalk.body.surrogate_kernel.sense`; the sensor noise of copy i at step k comes from a counter-based
generator keyed on (copy seed, k) (splitmix64), so a copy's episode depends on its seed alone, not on the others.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from neurowalk.body.surrogate_kernel import X, Y, act, sense
from neurowalk.compiled import jit, jit_parallel


@jit
def uniform(key: np.uint64, counter: int) -> float:
    """A uniform(-1, 1) draw from (key, counter) (splitmix64 of their mix)."""
    z = key + np.uint64(counter + 1) * np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return float(z >> np.uint64(11)) * (2.0 / 9007199254740992.0) - 1.0


@jit_parallel
def vector_step(
    ks: np.ndarray, states: np.ndarray, rings: np.ndarray, actions: np.ndarray, boxes: np.ndarray,
    nboxes: np.ndarray, keys: np.ndarray, circles: np.ndarray, rays: np.ndarray, us_range: float,
    grid: np.ndarray, table: np.ndarray, alpha: float, startup: int, dt: float, omega: float, sway_phase: float,
    noise_gain: float, noise_tau: float, reach: float, origin: np.ndarray, cell: float, visited: np.ndarray,
    free: np.ndarray, covered: np.ndarray, obs: np.ndarray, reward: np.ndarray, pose: np.ndarray,
    contacts: np.ndarray, scratch: np.ndarray,
) -> None:  # fmt: skip
    """One control step of every copy i: act with ``actions[i]``, count the newly entered cell, sense.

    Shapes: ks (N,) steps taken; states (N, RUN_STATE); rings (N, delay + 1, channels); actions (N, 2);
    boxes (N, m, 6) with ``nboxes`` (N,) rows used; keys (N,) uint64 noise keys; origin (N, 2) grid corner (m);
    visited, free (N, gx, gy) bool; covered (N,) visited free cells; out: obs (N, 2) distances (no echo: the
    range), reward (N,) m^2, pose (N, 3), contacts (N,) added to. scratch: (threads, channels + 4) work space
    of each of numba's threads (the copies are spread over them; each copy's result does not depend on which).
    """
    gx, gy = visited.shape[1], visited.shape[2]
    nc = table.shape[2]
    for i in numba.prange(ks.shape[0]):
        work = scratch[numba.get_thread_id()]
        cmd, noise, seen = work[:nc], work[nc : nc + 2], work[nc + 2 : nc + 4]
        b = boxes[i, : nboxes[i]]
        k = ks[i]
        n, yaw = act(k, states[i], rings[i], actions[i, 0], actions[i, 1], cmd, grid, table, alpha, startup, dt,
                     omega, sway_phase, circles, b, reach)  # fmt: skip
        contacts[i] += n
        k += 1
        ks[i] = k
        x, y = states[i, X], states[i, Y]
        pose[i, 0], pose[i, 1], pose[i, 2] = x, y, yaw
        cx, cy = math.floor((x - origin[i, 0]) / cell), math.floor((y - origin[i, 1]) / cell)
        reward[i] = 0.0
        if 0 <= cx < gx and 0 <= cy < gy and not visited[i, cx, cy]:
            visited[i, cx, cy] = True
            reward[i] = cell * cell
            if free[i, cx, cy]:
                covered[i] += 1
        noise[0], noise[1] = uniform(keys[i], 2 * k), uniform(keys[i], 2 * k + 1)
        sense(k, states[i], b, rays, us_range, omega, sway_phase, noise, noise_gain, noise_tau, seen)
        for r in range(2):
            obs[i, r] = seen[r] if seen[r] < us_range else us_range


@jit
def free_mask(boxes: np.ndarray, nboxes: int, x0: float, y0: float, cell: float, nx: int, ny: int,
              out: np.ndarray) -> None:  # fmt: skip
    """``out[i, j]`` (bool): the centre of grid cell (i, j) (corner ``x0, y0``, side ``cell``) lies in no box.

    The test of :meth:`~neurowalk.arenas.spec.Box.contains` on the rows of
    :func:`~neurowalk.body.surrogate.box_rows`: :meth:`~neurowalk.arenas.spec.ArenaSpec.free_cells` as a grid.
    """
    out[:, :] = False
    for i in range(nx):
        px = x0 + cell / 2 + i * cell
        for j in range(ny):
            py = y0 + cell / 2 + j * cell
            free = True
            for m in range(nboxes):
                dx, dy = px - boxes[m, 0], py - boxes[m, 1]
                u = dx * boxes[m, 2] + dy * boxes[m, 3]
                v = -dx * boxes[m, 3] + dy * boxes[m, 2]
                if abs(u) <= boxes[m, 4] and abs(v) <= boxes[m, 5]:
                    free = False
                    break
            out[i, j] = free
