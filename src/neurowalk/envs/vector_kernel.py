"""Compiled steps of the vectorised environments: N copies' motion, sensing and coverage in one call each.

``neurowalk/Explore-v0`` (:func:`vector_step`): each copy runs the surrogate's own
:func:`~neurowalk.body.surrogate_kernel.act` and :func:`~neurowalk.body.surrogate_kernel.sense`; the sensor noise
of copy i at step k comes from a counter-based generator keyed on (copy seed, k) (splitmix64), so a copy's episode
depends on its seed alone, not on the others.

``neurowalk/ExplorePhysics-v0`` (:func:`count_cells`, :func:`near_obstacles`): the bookkeeping after a
``mujoco.batch`` step, the same arithmetic, in the same order, as the single environment's NumPy code
(``ExploreTask.step``), so that each copy's numbers are the single run's bit for bit; the copies sense as AMOSII
does (:class:`~neurowalk.body.amosii_worlds.AmosIIWorlds`).
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
    ks: np.ndarray,
    states: np.ndarray,
    rings: np.ndarray,
    actions: np.ndarray,
    boxes: np.ndarray,
    nboxes: np.ndarray,
    keys: np.ndarray,
    circles: np.ndarray,
    rays: np.ndarray,
    us_range: float,
    grid: np.ndarray,
    table: np.ndarray,
    alpha: float,
    startup: int,
    dt: float,
    omega: float,
    sway_phase: float,
    noise_gain: float,
    noise_tau: float,
    reach: float,
    origin: np.ndarray,
    cell: float,
    visited: np.ndarray,
    free: np.ndarray,
    covered: np.ndarray,
    obs: np.ndarray,
    reward: np.ndarray,
    pose: np.ndarray,
    contacts: np.ndarray,
    scratch: np.ndarray,
) -> None:
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
        n, yaw = act(
            k,
            states[i],
            rings[i],
            actions[i, 0],
            actions[i, 1],
            cmd,
            grid,
            table,
            alpha,
            startup,
            dt,
            omega,
            sway_phase,
            circles,
            b,
            reach,
        )
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
def free_mask(
    boxes: np.ndarray, nboxes: int, x0: float, y0: float, cell: float, nx: int, ny: int, out: np.ndarray
) -> None:
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


@jit
def reported(dist: np.ndarray, obs_range: float, obs: np.ndarray) -> None:
    """The observations (N, 2) the environment reports of the copies' distances ``dist`` (N, 2) (m, inf: no echo):
    no echo as ``obs_range`` m, anything farther at most that."""
    for i in range(dist.shape[0]):
        for r in range(2):
            d = dist[i, r]
            obs[i, r] = min(d, obs_range) if math.isfinite(d) else obs_range


@jit
def count_cells(
    ids: np.ndarray,
    pose: np.ndarray,
    origin: np.ndarray,
    cell: float,
    visited: np.ndarray,
    free: np.ndarray,
    covered: np.ndarray,
    ks: np.ndarray,
    reward: np.ndarray,
    outside: np.ndarray,
    ring: np.ndarray,
    radius: float,
    stuck: np.ndarray,
) -> int:
    """One step's bookkeeping of copies ``ids`` at their new ``pose`` (N, 3): step count, reward, coverage, stuck;
    returns how many of them are off the grid.

    ``ks`` (N,) += 1; the grid cell (side ``cell`` m, corner ``origin`` (N, 2) m) of the trunk: if new in
    ``visited`` (N, gx, gy) bool, ``reward`` (N,) = cell^2 m^2 (else 0) and ``covered`` (N,) += 1 where ``free``;
    ``outside`` (N,): the cell is off the grid (left to the caller, reward 0 here). ``ring`` (N, W, 2): the last W
    positions (slot k % W; W = 0: no stuck test); ``stuck`` (N,): the last W positions lie within ``radius`` m of
    their mean (:func:`~neurowalk.envs.task.within_disc`'s sums, oldest first).
    """
    gx, gy, w = visited.shape[1], visited.shape[2], ring.shape[1]
    off = 0
    for i in ids:
        k = ks[i] + 1
        ks[i] = k
        x, y = pose[i, 0], pose[i, 1]
        cx, cy = math.floor((x - origin[i, 0]) / cell), math.floor((y - origin[i, 1]) / cell)
        reward[i] = 0.0
        outside[i] = not (0 <= cx < gx and 0 <= cy < gy)
        off += outside[i]
        if not outside[i] and not visited[i, cx, cy]:
            visited[i, cx, cy] = True
            reward[i] = cell * cell
            if free[i, cx, cy]:
                covered[i] += 1
        stuck[i] = False
        if w > 0:
            ring[i, k % w, 0], ring[i, k % w, 1] = x, y
            if k + 1 >= w:
                stuck[i] = _ring_within(ring[i], k, radius)
    return off


@jit
def _ring_within(ring: np.ndarray, k: int, radius: float) -> bool:
    """:func:`~neurowalk.envs.task.within_disc` of the positions of steps k + 1 - W .. k held in ``ring`` (W, 2)."""
    w = ring.shape[0]
    mx, my = 0.0, 0.0
    for j in range(w):
        s = (k + 1 + j) % w
        mx += ring[s, 0]
        my += ring[s, 1]
    mx, my = mx / w, my / w
    r2 = radius * radius
    for j in range(w):
        s = (k + 1 + j) % w
        if (ring[s, 0] - mx) ** 2 + (ring[s, 1] - my) ** 2 > r2:
            return False
    return True


@jit
def near_obstacles(
    ids: np.ndarray,
    geom_xpos: np.ndarray,
    robot: np.ndarray,
    robot_r: np.ndarray,
    centre: np.ndarray,
    frame: np.ndarray,
    half: np.ndarray,
    grow: np.ndarray,
    out: np.ndarray,
) -> int:
    """``out[i]`` (bool) for copies ``ids``: some robot geom's bounding sphere reaches some obstacle; returns how
    many do.

    ``geom_xpos`` (N, ngeom, 3) m; ``robot`` (N, R) the robot's geom ids, ``robot_r`` (N, R) their bounding radii
    plus margins (m). The (static) obstacles as boxes: ``centre`` (N, O, 3) m, ``frame`` (N, O, 9) their rotations
    (MuJoCo's row-major ``geom_xmat``), ``half`` (N, O, 3) half sizes (m), grown by ``grow`` (N, O) m (the margin;
    a geom that is no box: zero sizes, grown by its bounding radius and margin). MuJoCo makes a contact only where
    the two geoms come within their margin, so where this is False the copy touches no obstacle. One sphere around
    the whole robot is tested first; each geom only against the boxes that sphere reaches.
    """
    count = 0
    for i in ids:
        g0 = robot[i, 0]
        cx, cy, cz = geom_xpos[i, g0, 0], geom_xpos[i, g0, 1], geom_xpos[i, g0, 2]
        whole = 0.0  # radius (m) of a sphere around cx, cy, cz holding every robot geom's bounding sphere
        for b in range(robot.shape[1]):
            g = robot[i, b]
            d = math.sqrt(
                (geom_xpos[i, g, 0] - cx) ** 2 + (geom_xpos[i, g, 1] - cy) ** 2 + (geom_xpos[i, g, 2] - cz) ** 2
            )
            whole = max(whole, d + robot_r[i, b])
        near = False
        for a in range(centre.shape[1]):
            if not _reaches(cx, cy, cz, whole + grow[i, a], centre[i, a], frame[i, a], half[i, a]):
                continue
            for b in range(robot.shape[1]):
                g = robot[i, b]
                if _reaches(
                    geom_xpos[i, g, 0],
                    geom_xpos[i, g, 1],
                    geom_xpos[i, g, 2],
                    robot_r[i, b] + grow[i, a],
                    centre[i, a],
                    frame[i, a],
                    half[i, a],
                ):
                    near = True
                    break
            if near:
                break
        out[i] = near
        count += near
    return count


@jit
def _reaches(x: float, y: float, z: float, r: float, centre: np.ndarray, frame: np.ndarray, half: np.ndarray) -> bool:
    """Whether the sphere at (x, y, z) of radius r (m) reaches the box (``centre`` (3,), ``frame`` (9,) row-major
    rotation, ``half`` (3,) half sizes); 1 µm to spare for rounding."""
    px, py, pz = x - centre[0], y - centre[1], z - centre[2]
    d2 = 0.0  # squared distance from the point to the box
    for j in range(3):
        e = abs(frame[j] * px + frame[3 + j] * py + frame[6 + j] * pz) - half[j]
        if e > 0.0:
            d2 += e * e
    reach = r + 1e-6
    return d2 <= reach * reach


@jit
def first_bad_row(a: np.ndarray, low: np.ndarray, high: np.ndarray) -> int:
    """Index of the first row of ``a`` (N, d) with a value that is not finite or not within ``low``..``high`` (d,),
    or -1 where every row is good."""
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            if not low[j] <= a[i, j] <= high[j]:  # NaN fails both
                return i
    return -1
