"""Compiled hot loop of the planar surrogate: rays, sensory network, calibrated motion, collisions.

Everything here is plain arrays and numba; :mod:`neurowalk.body.surrogate` holds the Python side.
Geometry (m, rad): a box row is ``(cx, cy, cos(yaw), sin(yaw), half_x, half_y)``; the footprint is a
set of circles ``(x, y, r)`` in the trunk frame (x forward, y left); each ultrasonic ray is an origin
``(x, y)`` and a unit direction in the trunk frame.

Run state (one row, float64): ``x, y, yaw, vx, vy, w, sway, n1, n2`` (mean pose, lagged body-frame
velocity m/s, m/s, rad/s, lagged amplitude of the gait's yaw sway rad, ultrasonic noise); the motion
table has one channel per lagged quantity (vx, vy, w, sway) and the command delay line is a separate
``(delay + 1, channels)`` ring. The body's yaw is the mean yaw plus ``sway * sin(2 pi k / period +
phase)``: the trunk rocks with the gait, and the rays scan with it.
"""

from __future__ import annotations

import math

import numpy as np

from neurowalk.compiled import jit
from neurowalk.neural.sensory import STEER, sensory_input, sensory_step

X, Y, YAW, VX, VY, W, SWAY, N1, N2 = range(9)
RUN_STATE = 9
PUSH_PASSES = 8  # collision resolution passes per step (at most; stops when nothing overlaps)


@jit
def ray_boxes(ox: float, oy: float, dx: float, dy: float, boxes: np.ndarray, max_range: float) -> float:
    """Distance (m) along the unit ray (o, d) to the nearest box, ``inf`` if none within ``max_range``."""
    best = math.inf
    for i in range(boxes.shape[0]):
        cx, cy, c, s, hx, hy = boxes[i, 0], boxes[i, 1], boxes[i, 2], boxes[i, 3], boxes[i, 4], boxes[i, 5]
        rx, ry = ox - cx, oy - cy
        if rx * rx + ry * ry > (max_range + hx + hy) ** 2:
            continue
        px, py = c * rx + s * ry, -s * rx + c * ry
        ux, uy = c * dx + s * dy, -s * dx + c * dy
        t0, t1 = -math.inf, math.inf
        hit = True
        for p, u, h in ((px, ux, hx), (py, uy, hy)):
            if abs(u) < 1e-12:
                if abs(p) > h:
                    hit = False
            else:
                a, b = (-h - p) / u, (h - p) / u
                if a > b:
                    a, b = b, a
                t0, t1 = max(t0, a), min(t1, b)
        if hit and t0 <= t1 and t1 >= 0.0:
            t = max(t0, 0.0)
            if t < best:
                best = t
    return best if best <= max_range else math.inf


@jit
def push_out(state: np.ndarray, yaw: float, circles: np.ndarray, boxes: np.ndarray, reach: float) -> int:
    """Translate the body (heading ``yaw``) out of every box it overlaps; returns the overlaps seen."""
    hits = 0
    c, s = math.cos(yaw), math.sin(yaw)
    for _ in range(PUSH_PASSES):
        moved = False
        for i in range(boxes.shape[0]):
            cx, cy, bc, bs, hx, hy = boxes[i, 0], boxes[i, 1], boxes[i, 2], boxes[i, 3], boxes[i, 4], boxes[i, 5]
            if (state[X] - cx) ** 2 + (state[Y] - cy) ** 2 > (reach + hx + hy) ** 2:
                continue
            for j in range(circles.shape[0]):
                wx = state[X] + c * circles[j, 0] - s * circles[j, 1] - cx
                wy = state[Y] + s * circles[j, 0] + c * circles[j, 1] - cy
                r = circles[j, 2]
                px, py = bc * wx + bs * wy, -bs * wx + bc * wy  # circle centre in the box frame
                qx, qy = min(max(px, -hx), hx), min(max(py, -hy), hy)
                ex, ey = px - qx, py - qy
                d2 = ex * ex + ey * ey
                if d2 >= r * r:
                    continue
                if d2 > 0.0:
                    d = math.sqrt(d2)
                    mx, my = ex / d * (r - d), ey / d * (r - d)
                elif hx - abs(px) < hy - abs(py):  # centre inside: leave by the nearest face
                    mx, my = math.copysign(hx - abs(px) + r, px), 0.0
                else:
                    mx, my = 0.0, math.copysign(hy - abs(py) + r, py)
                state[X] += bc * mx - bs * my
                state[Y] += bs * mx + bc * my
                hits += 1
                moved = True
        if not moved:
            break
    return hits


@jit
def velocity_command(grid: np.ndarray, table: np.ndarray, o1: float, o2: float, out: np.ndarray) -> None:
    """Bilinear look-up of the motion table (g, g, n) at steering (o1, o2) into ``out`` (n,)."""
    g = grid.shape[0]
    a = min(max(o1, grid[0]), grid[g - 1])
    b = min(max(o2, grid[0]), grid[g - 1])
    i = 0
    while i < g - 2 and a > grid[i + 1]:
        i += 1
    j = 0
    while j < g - 2 and b > grid[j + 1]:
        j += 1
    fa = (a - grid[i]) / (grid[i + 1] - grid[i])
    fb = (b - grid[j]) / (grid[j + 1] - grid[j])
    for k in range(table.shape[2]):
        lo = table[i, j, k] * (1.0 - fb) + table[i, j + 1, k] * fb
        hi = table[i + 1, j, k] * (1.0 - fb) + table[i + 1, j + 1, k] * fb
        out[k] = lo * (1.0 - fa) + hi * fa


@jit
def move(state: np.ndarray, ring: np.ndarray, k: int, cmd: np.ndarray, alpha: float, dt: float) -> None:
    """Delay the command (n,) through ``ring``, low-pass it into the state (gain ``alpha``), integrate the pose."""
    slot = k % ring.shape[0]
    for m in range(ring.shape[1]):
        ring[slot, m] = cmd[m]
    old = ring[(k + 1) % ring.shape[0]]  # the command of ``delay`` steps ago (zeros at first)
    for m in range(ring.shape[1]):
        state[VX + m] += alpha * (old[m] - state[VX + m])
    mid = state[YAW] + 0.5 * state[W] * dt
    c, s = math.cos(mid), math.sin(mid)
    state[X] += (c * state[VX] - s * state[VY]) * dt
    state[Y] += (s * state[VX] + c * state[VY]) * dt
    yaw = state[YAW] + state[W] * dt
    state[YAW] = math.atan2(math.sin(yaw), math.cos(yaw))


@jit
def reach_of(circles: np.ndarray) -> float:
    """Farthest extent (m) of the footprint circles (k, 3) from the trunk centre."""
    reach = 0.0
    for j in range(circles.shape[0]):
        reach = max(reach, math.hypot(circles[j, 0], circles[j, 1]) + circles[j, 2])
    return reach


@jit
def sense(
    k: int,
    state: np.ndarray,
    boxes: np.ndarray,
    rays: np.ndarray,
    us_range: float,
    omega: float,
    sway_phase: float,
    noise: np.ndarray,
    noise_gain: float,
    noise_tau: float,
    seen: np.ndarray,
) -> None:
    """The ultrasonic readings at control step ``k`` into ``seen`` (2,) (m, inf = no echo), advancing the noise.

    ``noise``: this step's two uniform(-1, 1) draws; ``omega``: the sway's angular rate per step (rad).
    """
    yaw = state[YAW] + state[SWAY] * math.sin(omega * k + sway_phase)
    c, s = math.cos(yaw), math.sin(yaw)
    for r in range(2):
        ox = state[X] + c * rays[r, 0] - s * rays[r, 1]
        oy = state[Y] + s * rays[r, 0] + c * rays[r, 1]
        d = ray_boxes(ox, oy, c * rays[r, 2] - s * rays[r, 3], s * rays[r, 2] + c * rays[r, 3], boxes, us_range)
        state[N1 + r] += noise_gain * noise[r] - noise_tau * state[N1 + r]
        u = max(0.0, 1.0 - d / us_range) + state[N1 + r]
        seen[r] = us_range * (1.0 - u) if u > 0.0 else math.inf


@jit
def act(
    k: int,
    state: np.ndarray,
    ring: np.ndarray,
    o1: float,
    o2: float,
    cmd: np.ndarray,
    grid: np.ndarray,
    table: np.ndarray,
    alpha: float,
    startup: int,
    dt: float,
    omega: float,
    sway_phase: float,
    circles: np.ndarray,
    boxes: np.ndarray,
    reach: float,
) -> tuple[int, float]:
    """Control step ``k`` with steering (o1, o2): calibrated motion, then collisions resolved.

    Returns (overlaps resolved, the trunk's yaw after the step, rad, sway included, in (-pi, pi]).
    """
    if k < startup:
        cmd[:] = 0.0
    else:
        velocity_command(grid, table, o1, o2, cmd)
    move(state, ring, k, cmd, alpha, dt)
    yaw = state[YAW] + state[SWAY] * math.sin(omega * (k + 1) + sway_phase)
    hits = push_out(state, yaw, circles, boxes, reach)
    return hits, math.atan2(math.sin(yaw), math.cos(yaw))


@jit
def rollout(
    k0: int,
    k1: int,
    state: np.ndarray,
    ring: np.ndarray,
    sens: np.ndarray,
    sens_p: np.ndarray,
    fixed: bool,
    steer: np.ndarray,
    boxes: np.ndarray,
    circles: np.ndarray,
    rays: np.ndarray,
    us_range: float,
    grid: np.ndarray,
    table: np.ndarray,
    alpha: float,
    startup: int,
    dt: float,
    sway_period: float,
    sway_phase: float,
    noise_u: np.ndarray,
    noise_gain: float,
    noise_tau: float,
    out_pose: np.ndarray,
    out_in: np.ndarray,
    out_out: np.ndarray,
    out_b: np.ndarray,
    out_q: np.ndarray,
    out_us: np.ndarray,
    base: int = 0,
) -> int:
    """Control steps k0..k1-1 of one run, in place; row k - base of the outputs is after step k.

    Args:
        state: (8,) run state; ring: (delay + 1, 3) command delay line; sens: (8,) sensory network state
            (``sensory_step`` layout); sens_p: its params; fixed/steer: constant steering (2,) instead.
        boxes: (m, 6) obstacles; circles: (k, 3) footprint; rays: (2, 4) ultrasonic origin and direction
            (left, right); grid (g,), table (g, g, 4): calibrated vx, vy, w, sway; alpha: lag gain per step;
            startup: steps before the legs move; dt: control period (s); sway_period (steps), sway_phase (rad).
        noise_u: (k1 - k0, 2) uniform(-1, 1) draws of the coloured ultrasonic noise, row k - k0 for step k.
        out_pose (n, 3), out_in (n, 2), out_out (n, 2), out_b (n, 2), out_q (n, 2) the network's weights (left
            as they are with constant steering), out_us (n, 2) distances as the network saw them (m, inf = no
            echo); n >= k1 - base.
        base: the step of the outputs' row 0 (0: the whole run's arrays; k0: one chunk's).

    Returns:
        The number of collision overlaps resolved.
    """
    reach = reach_of(circles)
    cmd = np.zeros(table.shape[2])
    inp = np.zeros(2)
    seen = np.zeros(2)
    hits = 0
    omega = 2.0 * math.pi / sway_period
    for k in range(k0, k1):
        sense(k, state, boxes, rays, us_range, omega, sway_phase, noise_u[k - k0], noise_gain, noise_tau, seen)
        i = k - base
        for r in range(2):
            out_us[i, r] = seen[r]
            inp[r] = sensory_input(seen[r], sens_p)
        if fixed:
            o1, o2 = steer[0], steer[1]
            inp[0], inp[1] = -1.0, -1.0
        else:
            sensory_step(sens, inp[0], inp[1], sens_p)
            o1, o2 = sens[STEER], sens[STEER + 1]
        n, yaw = act(
            k, state, ring, o1, o2, cmd, grid, table, alpha, startup, dt, omega, sway_phase, circles, boxes, reach
        )
        hits += n
        out_pose[i, 0], out_pose[i, 1], out_pose[i, 2] = state[X], state[Y], yaw
        out_in[i, 0], out_in[i, 1] = inp[0], inp[1]
        out_out[i, 0], out_out[i, 1] = o1, o2
        if not fixed:
            out_b[i, 0], out_b[i, 1], out_q[i, 0], out_q[i, 1] = sens[4], sens[5], sens[6], sens[7]
    return hits
