"""Compiled passes behind the costly metrics of :mod:`neurowalk.metrics` (numba, same answers bit for bit).

Positions are ``xy`` (T, 2) float64 in m, one row per control step. A *stretch* is ``window`` consecutive rows;
it *fits* when every position lies within ``radius`` m of the stretch's mean (squared distances compared with
``radius * radius``), as numpy computes it in :mod:`neurowalk.metrics`.

The mean numpy computes depends on its summation order (sequential or pairwise, by numpy version and memory
layout). These passes sum in their own order and keep a proven error bound: every summation order of the
``window`` values lies within ``delta`` of the true mean (Higham's bound, ``gamma_n * sum|x|``), so a position
that lies farther than ``radius + 2 delta`` (or nearer than ``radius - 2 delta``) from this mean, with a relative
slack :data:`SLACK` for the roundings of the squares, lies outside (inside) the disc for numpy too. A stretch
no position of which is that close to the edge is decided here; the rest (exact ties, e.g. points at exactly
``radius``) come back as *undecided* and :mod:`neurowalk.metrics` checks them with numpy itself. Everything else
(block extremes, the sequential cumulative sum, comparisons) is exact arithmetic that numpy does alike.
"""

from __future__ import annotations

import math

import numpy as np

from neurowalk.compiled import jit

UNIT = 2.0**-53
"""Unit roundoff of float64."""
SLACK = 1e-12
"""Relative slack of the undecided band (far above the few unit roundoffs of a squared distance)."""
HUGE = 1e150
"""Beyond this (m) a squared distance could overflow: such a stretch is left undecided."""


@jit
def _nan_max(a: float, b: float) -> float:
    """``np.maximum(a, b)``: the larger, NaN if either is NaN."""
    return a if (a >= b or a != a) else b


@jit
def block_stats(xy: np.ndarray, stride: int, blocks: int) -> np.ndarray:
    """(blocks, 7) per block of ``stride`` rows (block j: rows j*stride .. j*stride + stride - 1; rows past the
    end repeat the last row): max x, max y, min x, min y (NaN if any is NaN), then over its real rows only:
    sum x, sum y (in row order) and the largest |coordinate| (m)."""
    n = xy.shape[0]
    out = np.empty((blocks, 7))
    for j in range(blocks):
        hx, hy, lx, ly = -math.inf, -math.inf, math.inf, math.inf
        sx, sy, a = 0.0, 0.0, 0.0
        for i in range(j * stride, (j + 1) * stride):
            r = min(i, n - 1)
            x, y = xy[r, 0], xy[r, 1]
            hx, hy = _nan_max(hx, x), _nan_max(hy, y)
            lx, ly = -_nan_max(-lx, -x), -_nan_max(-ly, -y)
            if i < n:
                sx += x
                sy += y
                a = max(a, abs(x), abs(y))
        out[j, 0], out[j, 1], out[j, 2], out[j, 3] = hx, hy, lx, ly
        out[j, 4], out[j, 5], out[j, 6] = sx, sy, a
    return out


@jit
def stretch_fits(xy: np.ndarray, s: int, window: int, radius: float, stride: int, stats: np.ndarray) -> int:
    """Whether rows [s, s + window) fit in the disc (see the module doc): 1 yes, 0 no, -1 undecided.

    ``stats``: :func:`block_stats` of ``xy`` with the same ``stride``: whole blocks are summed, and bounded, from
    it. A block extreme decisively outside the disc is a point outside; a bounding box decisively inside it holds
    every point (rounding is monotonic: no computed squared distance exceeds the box's); only a stretch that
    neither settles is checked point by point.
    """
    e = s + window
    jf, je = -(-s // stride), e // stride  # whole blocks [jf, je) inside the stretch
    if je <= jf:
        jf, je = e, e  # no whole block: sum row by row
    head, tail = min(jf * stride, e), max(je * stride, s)
    sx, sy, a = 0.0, 0.0, 0.0
    hx, hy, lx, ly = -math.inf, -math.inf, math.inf, math.inf
    for i in range(s, head):
        x, y = xy[i, 0], xy[i, 1]
        sx += x
        sy += y
        a = max(a, abs(x), abs(y))
        hx, hy, lx, ly = max(hx, x), max(hy, y), min(lx, x), min(ly, y)
    for j in range(jf, je):
        sx += stats[j, 4]
        sy += stats[j, 5]
        a = max(a, stats[j, 6])
        hx, hy, lx, ly = max(hx, stats[j, 0]), max(hy, stats[j, 1]), min(lx, stats[j, 2]), min(ly, stats[j, 3])
    for i in range(tail, e):
        x, y = xy[i, 0], xy[i, 1]
        sx += x
        sy += y
        a = max(a, abs(x), abs(y))
        hx, hy, lx, ly = max(hx, x), max(hy, y), min(lx, x), min(ly, y)
    if not (math.isfinite(sx) and math.isfinite(sy)):  # a NaN or inf row: no fit for numpy
        for i in range(s, e):
            if not (math.isfinite(xy[i, 0]) and math.isfinite(xy[i, 1])):
                return 0
        return -1  # an overflowing sum of finite values
    if a > HUGE:
        return -1
    mx, my = sx / window, sy / window
    delta = 2.0 * (4.0 * window + 4.0) * UNIT * a  # twice the bound on |numpy's mean - this mean|
    r_out = (radius * (1.0 + SLACK) + 2.0 * delta) * (1.0 + SLACK)
    r_in = (radius * (1.0 - SLACK) - 2.0 * delta) * (1.0 - SLACK)
    out2 = r_out * r_out
    in2 = r_in * r_in if r_in > 0.0 else -1.0
    for j in range(jf, je):  # a block's extreme coordinate belongs to one of its points
        ex = max(stats[j, 0] - mx, mx - stats[j, 2])
        ey = max(stats[j, 1] - my, my - stats[j, 3])
        if ex * ex > out2 or ey * ey > out2:
            return 0
    fx, fy = max(hx - mx, mx - lx), max(hy - my, my - ly)
    if fx * fx + fy * fy <= in2:
        return 1
    undecided = False
    for i in range(s, e):
        dx, dy = xy[i, 0] - mx, xy[i, 1] - my
        d2 = dx * dx + dy * dy
        if d2 > out2:
            return 0
        if not d2 <= in2:
            undecided = True
    return -1 if undecided else 1


@jit
def _wide(stats: np.ndarray, j0: int, j1: int, radius: float) -> bool:
    """True if the whole blocks [j0, j1) span decisively more than the disc's diameter in x or y."""
    if j1 <= j0:
        return False
    hx, hy, lx, ly = stats[j0, 0], stats[j0, 1], stats[j0, 2], stats[j0, 3]
    for j in range(j0 + 1, j1):
        hx, hy = max(hx, stats[j, 0]), max(hy, stats[j, 1])
        lx, ly = min(lx, stats[j, 2]), min(ly, stats[j, 3])
    limit = 2.0 * radius * (1.0 + SLACK)
    return hx - lx > limit or hy - ly > limit


@jit
def ever_fits(xy: np.ndarray, window: int, radius: float, stride: int) -> tuple[bool, np.ndarray]:
    """:func:`neurowalk.metrics.ever_trapped`'s stretches (every ``stride`` rows from 0, and the last one).

    Returns (some stretch surely fits, (k,) int64 starts of the undecided stretches; empty when one fits).
    """
    n = xy.shape[0]
    none = np.empty(0, dtype=np.int64)
    if n < window:
        return False, none
    stats = block_stats(xy, stride, -(-n // stride))
    todo = []
    last = n - window
    s = 0
    while True:
        if not _wide(stats, -(-s // stride), (s + window) // stride, radius):
            fit = stretch_fits(xy, s, window, radius, stride, stats)
            if fit == 1:
                return True, none
            if fit == -1:
                todo.append(s)
        if s == last:
            break
        s = s + stride if s + stride <= last else last
    out = np.empty(len(todo), dtype=np.int64)
    for i in range(len(todo)):
        out[i] = todo[i]
    return False, out


@jit
def _max_table(v: np.ndarray, levels: int) -> np.ndarray:
    """(levels, L) sparse table of ``v`` (L,): row k, column j is the NaN-propagating max of v[j : j + 2**k]."""
    n = v.shape[0]
    t = np.full((levels, n), math.nan)
    t[0] = v
    for k in range(1, levels):
        h = 1 << (k - 1)
        for j in range(n - (1 << k) + 1):
            t[k, j] = _nan_max(t[k - 1, j], t[k - 1, j + h])
    return t


@jit
def _range_max(t: np.ndarray, j: int, count: int) -> float:
    """NaN-propagating max of v[j : j + count] from its :func:`_max_table`; ``count`` 0 gives max(v[j], v[-1]),
    as the doubling running maximum of :mod:`neurowalk.metrics` does for a zero width."""
    if count == 0:
        return _nan_max(t[0, j], t[0, t.shape[1] - 1])
    k = 0
    while (2 << k) <= count:
        k += 1
    return _nan_max(t[k, j], t[k, j + count - (1 << k)])


@jit
def mark_stretches(n: int, starts: np.ndarray, window: int) -> np.ndarray:
    """(n,) bool: the rows inside some stretch [s, s + ``window``) for s in ``starts`` (k,) int64 (rows past ``n``
    ignored), by a running count of the stretches open at each row."""
    cover_count = np.zeros(n + window + 1, dtype=np.int64)
    for s in starts:
        cover_count[s] += 1
        cover_count[s + window] -= 1
    marked = np.zeros(n, dtype=np.bool_)
    inside = 0
    for i in range(n):
        inside += cover_count[i]
        marked[i] = inside > 0
    return marked


@jit
def fitting_starts(xy: np.ndarray, window: int, radius: float, stride: int) -> tuple[np.ndarray, np.ndarray]:
    """The stretches of :func:`neurowalk.metrics.wedged_periods` that fit, decided as its numpy code decides them.

    Stretches start every ``stride`` rows and at ``T - window``. One is *wide* (does not fit) where the maxima
    over its first ``inner`` whole blocks of ``stride`` rows (``inner``: the fewest any stretch holds) span more
    than ``2 radius`` in x or y (none is wide where ``inner`` is 0: no block bounds the stretch); else *sure*
    (fits) where the bounding box of the ``window // stride + 2`` blocks from its first lies within ``radius``
    of its mean (from the running sum); else it fits if :func:`stretch_fits` says so. All of this is the numpy
    code's arithmetic, operation for operation.

    Returns:
        (j,) int64 starts of the stretches that surely fit, ascending, and the (k,) int64 starts of undecided
        stretches (numpy checks them).
    """
    n = xy.shape[0]
    if n < window:
        return np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
    last = n - window
    count = last // stride + 1 + (1 if last % stride else 0)
    starts = np.empty(count, dtype=np.int64)
    for i in range(count):
        starts[i] = min(i * stride, last)
    cover = -(-window // stride) + 1  # blocks that cover any stretch
    nb = -(-n // stride)
    stats = block_stats(xy, stride, nb + cover)
    inner = n
    for s in starts:
        inner = min(inner, (s + window) // stride - (-(-s // stride)))
    levels = 1
    while (1 << levels) <= max(inner, cover):
        levels += 1
    hi_x, hi_y = _max_table(stats[:, 0].copy(), levels), _max_table(stats[:, 1].copy(), levels)
    nlo_x, nlo_y = _max_table(-stats[:, 2], levels), _max_table(-stats[:, 3], levels)
    csum = np.zeros((n + 1, 2))
    csum[1] = xy[0]
    for i in range(1, n):
        csum[i + 1, 0] = csum[i, 0] + xy[i, 0]
        csum[i + 1, 1] = csum[i, 1] + xy[i, 1]
    two_r, r2 = 2.0 * radius, radius * radius
    fits = []
    todo = []
    for s in starts:
        f = -(-s // stride)
        if inner > 0 and _range_max(hi_x, f, inner) + _range_max(nlo_x, f, inner) > two_r:
            continue
        if inner > 0 and _range_max(hi_y, f, inner) + _range_max(nlo_y, f, inner) > two_r:
            continue
        mx = (csum[s + window, 0] - csum[s, 0]) / window
        my = (csum[s + window, 1] - csum[s, 1]) / window
        at = s // stride
        fx = _nan_max(_range_max(hi_x, at, cover) - mx, mx + _range_max(nlo_x, at, cover))
        fy = _nan_max(_range_max(hi_y, at, cover) - my, my + _range_max(nlo_y, at, cover))
        fit = 1 if fx * fx + fy * fy <= r2 else stretch_fits(xy, s, window, radius, stride, stats)
        if fit == 1:
            fits.append(s)
        elif fit == -1:
            todo.append(s)
    return _as_array(fits), _as_array(todo)


@jit
def _as_array(values: list[int]) -> np.ndarray:
    """(k,) int64 array of the ints ``values`` (an empty list too)."""
    out = np.empty(len(values), dtype=np.int64)
    for i in range(len(values)):
        out[i] = values[i]
    return out


@jit
def heading_ranges(yaw: np.ndarray, starts: np.ndarray, window: int) -> np.ndarray:
    """(k,) range, max minus min (rad), of ``yaw`` (T,) unwrapped heading over each stretch [s, s + ``window``)
    for s in ``starts`` (k,) int64 (each within the rows); NaN where the stretch holds a NaN.

    From sparse tables of the maxima of ``yaw`` and of ``-yaw`` (O(T log window) once, O(1) a stretch): max and
    min are exact, so the range is the one rounding of their difference, as numpy's ``ptp`` gives it.
    """
    out = np.empty(starts.shape[0])
    if starts.shape[0] == 0:
        return out
    levels = 1
    while (1 << levels) <= window:
        levels += 1
    hi, nlo = _max_table(yaw.copy(), levels), _max_table(-yaw, levels)
    for i in range(starts.shape[0]):
        s = starts[i]
        top, neg_bottom = _range_max(hi, s, window), _range_max(nlo, s, window)
        out[i] = top - (-neg_bottom)
    return out


@jit
def visited_count(xy: np.ndarray, x0: float, y0: float, cell: float, keys: np.ndarray) -> int:
    """How many of the cells ``keys`` (k, 2) int64 (``floor((centre - (x0, y0)) / cell)``) some row of ``xy`` is in.

    A row's cell is ``floor((xy - (x0, y0)) / cell)`` (m, m, m); rows with NaN or outside the keys' range count
    for no cell.
    """
    if keys.shape[0] == 0:
        return 0
    kx0, kx1, ky0, ky1 = keys[0, 0], keys[0, 0], keys[0, 1], keys[0, 1]
    for k in range(keys.shape[0]):
        kx0, kx1 = min(kx0, keys[k, 0]), max(kx1, keys[k, 0])
        ky0, ky1 = min(ky0, keys[k, 1]), max(ky1, keys[k, 1])
    seen = np.zeros((kx1 - kx0 + 1, ky1 - ky0 + 1), dtype=np.bool_)
    for i in range(xy.shape[0]):
        fx = np.floor((xy[i, 0] - x0) / cell)
        fy = np.floor((xy[i, 1] - y0) / cell)
        if fx >= kx0 and fx <= kx1 and fy >= ky0 and fy <= ky1:
            seen[int(fx) - kx0, int(fy) - ky0] = True
    count = 0
    for k in range(keys.shape[0]):
        if seen[keys[k, 0] - kx0, keys[k, 1] - ky0]:
            count += 1
    return count


@jit
def turn_runs(state: np.ndarray, max_gap: int) -> np.ndarray:
    """(k, 3) int64 rows (start, end, direction) of the runs of one commanded turn in ``state`` (T,) int64
    (+1 right, -1 left, 0 none), gaps of up to ``max_gap`` steps with no turn bridged."""
    n = state.shape[0]
    runs = []
    k = 0
    while k < n:
        if state[k] == 0:
            k += 1
            continue
        direction, start, end = state[k], k, k
        j = k + 1
        while j < n and (state[j] == direction or (state[j] == 0 and j - end <= max_gap)):
            if state[j] == direction:
                end = j
            j += 1
        runs.append((start, end, direction))
        k = end + 1
    out = np.empty((len(runs), 3), dtype=np.int64)
    for i in range(len(runs)):
        out[i, 0], out[i, 1], out[i, 2] = runs[i]
    return out


@jit
def _mod(a: float, b: float) -> float:
    """``np.mod(a, b)`` for b > 0 (numpy's ``npy_remainder``: fmod, moved to the divisor's sign)."""
    m = np.fmod(a, b)
    if m != 0.0:  # NaN too, as numpy's ``if (mod)``
        if (b < 0.0) != (m < 0.0):
            m += b
    else:
        m = math.copysign(0.0, b)
    return m


@jit
def unwrap(p: np.ndarray) -> np.ndarray:
    """``np.unwrap(p)`` (T,) rad with its default period 2 pi, operation for operation: a jump of pi or more
    between neighbours is wrapped into [-pi, pi] and the corrections add up in row order."""
    n = p.shape[0]
    up = np.empty(n)
    if n == 0:
        return up
    up[0] = p[0]
    period = 2.0 * math.pi
    high = period / 2.0
    low = -high
    total = 0.0
    for i in range(1, n):
        dd = p[i] - p[i - 1]
        if abs(dd) < high:
            ph = 0.0
        else:
            ddmod = _mod(dd - low, period) + low
            if ddmod == low and dd > 0.0:
                ddmod = high
            ph = ddmod - dd
        total = ph if i == 1 else total + ph
        up[i] = p[i] + total
    return up


@jit
def step_lengths(xy: np.ndarray) -> np.ndarray:
    """(T - 1,) lengths (m) of the steps between neighbouring rows of ``xy`` (T, 2): sqrt(dx * dx + dy * dy)."""
    n = xy.shape[0]
    out = np.empty(max(n - 1, 0))
    for i in range(n - 1):
        dx, dy = xy[i + 1, 0] - xy[i, 0], xy[i + 1, 1] - xy[i, 1]
        out[i] = math.sqrt(dx * dx + dy * dy)
    return out


@jit
def turn_state(outputs: np.ndarray, threshold: float) -> np.ndarray:
    """(T,) int64 commanded turn from steering ``outputs`` (T, >= 2): +1 where O1 - O2 > ``threshold``, -1 where
    it is below ``-threshold``, else 0 (NaN too)."""
    n = outputs.shape[0]
    out = np.empty(n, dtype=np.int64)
    for i in range(n):
        d = outputs[i, 0] - outputs[i, 1]
        out[i] = 1 if d > threshold else (-1 if d < -threshold else 0)
    return out
