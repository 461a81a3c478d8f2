"""The metrics' numpy implementations before their compiled passes (neurowalk.metrics_kernel): the reference.

Copied unchanged from ``neurowalk/metrics.py`` as it stood before the compiled passes (commit d1ff68b); the tests
check that today's functions give exactly these answers (same floats, same booleans).
"""

from __future__ import annotations

import math

import numpy as np

from neurowalk.arenas.spec import ArenaSpec
from neurowalk.metrics import BLIND_M, WEDGE_MIN_S, WEDGE_RADIUS


def path_length(pose: np.ndarray) -> float:
    """Length (m) of the trunk centre's path, pose (T, 3)."""
    return float(np.sum(np.linalg.norm(np.diff(pose[:, :2], axis=0), axis=1)))


def heading_change(pose: np.ndarray, start_yaw: float | None = None) -> float:
    """Net change of heading (rad, counter-clockwise positive), unwrapped over the whole path."""
    yaw = np.unwrap(np.concatenate([[pose[0, 2] if start_yaw is None else start_yaw], pose[:, 2]]))
    return float(yaw[-1] - yaw[0])


def ever_trapped(pose: np.ndarray, *, window: int = 3000, radius: float = 0.5, stride: int = 100) -> bool:
    """True if any ``window`` steps (starting every ``stride`` steps) stayed within ``radius`` m of their mean.

    :func:`trapped` asks this of the last window only; a robot that got stuck for ``window`` steps and
    then got out counts here.
    """
    xy = pose[:, :2]
    starts = list(range(0, xy.shape[0] - window + 1, stride))
    if xy.shape[0] >= window and starts[-1] != xy.shape[0] - window:
        starts.append(xy.shape[0] - window)
    for s in starts:
        seg = xy[s : s + window]
        if np.max(np.sum((seg - seg.mean(axis=0)) ** 2, axis=1)) <= radius * radius:
            return True
    return False


def coverage(pose: np.ndarray, arena: ArenaSpec, cell: float = 0.25) -> float | None:
    """Fraction of the arena's free ``cell``-sized cells the trunk centre visited (None if unbounded)."""
    if arena.bounds is None:
        return None
    free = arena.free_cells(cell)
    if len(free) == 0:
        return None
    x0, _, y0, _ = arena.bounds
    key = lambda p: np.floor((p - [x0, y0]) / cell).astype(np.int64)  # noqa: E731
    visited = {tuple(k) for k in key(pose[:, :2])}
    return float(np.mean([tuple(k) in visited for k in key(free)]))


def turn_state(outputs: np.ndarray, threshold: float = 1.0) -> np.ndarray:
    """(T,) commanded turn per step from steering (O1, O2): +1 right (O1 - O2 > threshold), -1 left, 0 none."""
    d = outputs[:, 0] - outputs[:, 1]
    return np.where(d > threshold, 1, np.where(d < -threshold, -1, 0))


def latched_turn_share(outputs: np.ndarray, threshold: float = 1.0) -> float:
    """Share of the steps (rows of ``outputs``, (T, 2) steering) commanding a turn in the more frequent direction.

    Near 1 for a latched spin (the turn never switches off), near 0 for walking ahead.
    """
    if len(outputs) == 0:
        return 0.0
    s = turn_state(outputs, threshold)
    return float(max(np.count_nonzero(s > 0), np.count_nonzero(s < 0)) / len(s))


def direction_switches(outputs: np.ndarray, threshold: float = 1.0) -> int:
    """Number of reversals of the commanded turn (right ↔ left), ignoring steps with no turn.

    Many switches in a short time are the oscillation between two obstacles of paper Fig. 3B.
    """
    s = turn_state(outputs, threshold)
    s = s[s != 0]
    return int(np.count_nonzero(s[1:] != s[:-1])) if s.size else 0


def avoidance_episodes(
    outputs: np.ndarray, pose: np.ndarray, *, threshold: float = 1.0, max_gap: int = 5
) -> list[dict]:
    """Turning episodes: runs of a commanded turn in one direction (gaps up to ``max_gap`` steps bridged).

    Returns one dict per episode: ``start``, ``end`` (step indices), ``direction`` (+1 right, -1
    left) and ``turn_deg`` (the heading change over the episode, degrees, counter-clockwise +).
    """
    s = turn_state(outputs, threshold)
    yaw = np.unwrap(pose[:, 2])
    episodes: list[dict] = []
    k, n = 0, len(s)
    while k < n:
        if s[k] == 0:
            k += 1
            continue
        direction, start, end = int(s[k]), k, k
        j = k + 1
        while j < n and (s[j] == direction or (s[j] == 0 and j - end <= max_gap)):
            if s[j] == direction:
                end = j
            j += 1
        episodes.append(
            {
                "start": start,
                "end": end,
                "direction": direction,
                "turn_deg": float(np.degrees(yaw[end] - yaw[max(start - 1, 0)])),
            }
        )
        k = end + 1
    return episodes


def _running_max(a: np.ndarray, w: int) -> np.ndarray:
    """(m - w + 1, ...) maxima of ``a[i : i + w]`` along axis 0, by doubling (O(m log w))."""
    r, k = a, 1
    while 2 * k <= w:
        r, k = np.maximum(r[:-k], r[k:]), 2 * k  # r[i] = max a[i : i + k]
    m = len(a) - w + 1
    return np.maximum(r[:m], r[w - k : w - k + m])


def _fitting_windows(xy: np.ndarray, window: int, radius: float, stride: int) -> np.ndarray:
    """(T,) bool: rows inside some ``window``-row stretch (started every ``stride`` rows, and at the end) whose
    positions all lie within ``radius`` of their mean.

    Cheap bounds first, from the extremes of blocks of ``stride`` rows: a stretch whose whole blocks span more
    than the disc's diameter in x or y cannot fit; one whose covering blocks' bounding box lies within the disc
    around the stretch's mean fits. Only the stretches in between are checked point by point.
    """
    n = len(xy)
    marked = np.zeros(n, dtype=bool)
    if n < window:
        return marked
    starts = np.arange(0, n - window + 1, stride)
    if starts[-1] != n - window:
        starts = np.append(starts, n - window)
    cover = -(-window // stride) + 1  # blocks that cover any stretch
    nb = -(-n // stride)
    padded = np.concatenate([xy, np.repeat(xy[-1:], (nb + cover) * stride - n, axis=0)])  # repeats add no extremes
    blocks = padded.reshape(nb + cover, stride, 2)
    hi, lo = blocks.max(axis=1), blocks.min(axis=1)  # (nb + cover, 2) extremes of each block
    first, stop = -(-starts // stride), (starts + window) // stride  # whole blocks inside each stretch
    inner = int(np.min(stop - first))
    if inner < 0:  # the last stretch lies inside one block: its blocks cannot bound it
        raise ValueError(f"window ({window} rows) shorter than stride ({stride}): the blocks cannot bound it")
    wide = np.zeros(len(starts), dtype=bool)  # a stretch with no whole block: no cheap bound says it is wide
    if inner > 0:
        wide = np.any((_running_max(hi, inner) + _running_max(-lo, inner))[first] > 2.0 * radius, axis=1)
    csum = np.vstack([np.zeros((1, 2)), np.cumsum(xy, axis=0)])
    mean = (csum[starts + window] - csum[starts]) / window  # (m, 2)
    at = starts // stride  # the blocks from here on cover the stretch
    box_hi, box_lo = _running_max(hi, cover)[at], -_running_max(-lo, cover)[at]
    far = np.maximum(box_hi - mean, mean - box_lo)  # (m, 2) farthest covering-box extent from the mean
    sure = np.sum(far**2, axis=1) <= radius * radius
    for s in starts[sure & ~wide]:
        marked[s : s + window] = True
    views = np.lib.stride_tricks.sliding_window_view(xy, window, axis=0)  # (n - window + 1, 2, window), no copy
    todo = starts[~sure & ~wide]
    for k in range(0, len(todo), 256):  # point by point, 256 stretches at a time
        chunk = views[todo[k : k + 256]]
        d2 = np.sum((chunk - chunk.mean(axis=2, keepdims=True)) ** 2, axis=1)
        for s in todo[k : k + 256][np.max(d2, axis=1) <= radius * radius]:
            marked[s : s + window] = True
    return marked


def wedged_periods(
    pose: np.ndarray,
    *,
    control_hz: float = 10.0,
    radius: float = WEDGE_RADIUS,
    min_s: float = WEDGE_MIN_S,
    us_distance: np.ndarray | None = None,
    contact: np.ndarray | None = None,
    blind_m: float = BLIND_M,
    stride: int = 10,
    blind: np.ndarray | None = None,
) -> list[dict]:
    """Periods in which the robot stayed put: its trunk centre within a small disc for more than ``min_s`` s.

    A control step is wedged if it lies in a stretch of more than ``min_s`` seconds (started every ``stride``
    steps) whose trunk positions all lie within ``radius`` of their mean, as in :func:`trapped`; a period is a
    maximal run of wedged steps. Overlapping stretches join, so a period can outgrow the disc a little where
    the robot creeps (``extent_m`` says by how much).

    Args:
        pose: (T, 3) trunk pose per control step (x m, y m, yaw rad).
        control_hz: control steps per second.
        radius: disc radius (m), default :data:`WEDGE_RADIUS` = 0.3 m.
        min_s: a stretch must last longer than this (s), default :data:`WEDGE_MIN_S` = 100 s.
        us_distance: (T, 2) ultrasonic readings (m, inf = no echo), or None (cause "both rays blind" untested).
        contact: (T,) > 0 where the robot's trunk or legs touched an obstacle (NaN = not known), or None.
        blind_m: readings at or beyond this (m) count as blind.
        stride: steps between the starts of the stretches tried.
        blind: (T,) bool, both rays blind, instead of ``us_distance`` (e.g. kept by a long run in place of it).

    Returns:
        One dict per period, in time order: ``start``, ``end`` (first and last control step, inclusive),
        ``duration_s``, ``centre`` ([x, y] m, mean position), ``extent_m`` (largest distance from it),
        ``blind_fraction`` and ``contact_fraction`` (share of its steps with both rays blind / with body contact
        among those where it is known; None where not given) and ``cause``: "both rays blind" when both rays
        were blind for more than half of it, else "body contact" when the body touched an obstacle for more than
        half of it, else "other".
    """
    if not control_hz > 0 or not radius > 0 or not min_s > 0 or stride < 1:
        raise ValueError(
            f"need control_hz, radius, min_s > 0 and stride >= 1, got {control_hz}, {radius}, {min_s}, {stride}"
        )
    xy = np.asarray(pose, dtype=float)[:, :2]
    window = math.floor(min_s * control_hz + 1e-9) + 1  # more than min_s seconds
    marked = _fitting_windows(xy, window, radius, stride)
    if blind is None and us_distance is not None:
        blind = np.all(np.asarray(us_distance) >= blind_m, axis=1)
    touch = None if contact is None else np.asarray(contact, dtype=float)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], marked.astype(np.int8), [0]])))
    periods: list[dict] = []
    for s, e in zip(edges[::2], edges[1::2], strict=True):  # rows [s, e)
        centre = xy[s:e].mean(axis=0)
        fb = None if blind is None else float(np.mean(blind[s:e]))
        known = None if touch is None else touch[s:e][np.isfinite(touch[s:e])]
        fc = None if known is None or known.size == 0 else float(np.mean(known > 0))
        cause = (
            "both rays blind"
            if fb is not None and fb > 0.5
            else ("body contact" if fc is not None and fc > 0.5 else "other")
        )
        periods.append(
            {
                "start": int(s),
                "end": int(e - 1),
                "duration_s": float((e - s) / control_hz),
                "centre": centre.tolist(),
                "extent_m": float(np.max(np.linalg.norm(xy[s:e] - centre, axis=1))),
                "blind_fraction": fb,
                "contact_fraction": fc,
                "cause": cause,
            }
        )
    return periods
