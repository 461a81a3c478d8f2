"""Behaviour metrics: pure functions of a trajectory's arrays (poses in m and rad, one row per step)."""

from __future__ import annotations

import numpy as np

from neurowalk.arenas.spec import ArenaSpec


def path_length(pose: np.ndarray) -> float:
    """Length (m) of the trunk centre's path, pose (T, 3)."""
    return float(np.sum(np.linalg.norm(np.diff(pose[:, :2], axis=0), axis=1)))


def heading_change(pose: np.ndarray, start_yaw: float | None = None) -> float:
    """Net change of heading (rad, counter-clockwise positive), unwrapped over the whole path."""
    yaw = np.unwrap(np.concatenate([[pose[0, 2] if start_yaw is None else start_yaw], pose[:, 2]]))
    return float(yaw[-1] - yaw[0])


def forward_displacement(pose: np.ndarray, start: tuple[float, float, float]) -> float:
    """Displacement (m) along the start heading: positive forward, negative backward."""
    d = pose[-1, :2] - np.asarray(start[:2])
    return float(d @ np.array([np.cos(start[2]), np.sin(start[2])]))


def trapped(pose: np.ndarray, *, window: int = 3000, radius: float = 0.5) -> bool:
    """True if the last ``window`` steps stayed within a disc of ``radius`` (m) around their mean.

    False when the trajectory is shorter than the window (too short to tell).
    """
    if pose.shape[0] < window:
        return False
    tail = pose[-window:, :2]
    return bool(np.max(np.linalg.norm(tail - tail.mean(axis=0), axis=1)) <= radius)


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


def escaped(pose: np.ndarray, arena: ArenaSpec) -> bool | None:
    """Whether the trunk centre ever entered the arena's exit region (None if it has none)."""
    if arena.exit_region is None:
        return None
    x0, x1, y0, y1 = arena.exit_region
    x, y = pose[:, 0], pose[:, 1]
    return bool(np.any((x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)))


def exit_step(pose: np.ndarray, arena: ArenaSpec) -> int | None:
    """First control step (row index) at which the trunk centre is in the exit region; None if never or none."""
    if arena.exit_region is None:
        return None
    x0, x1, y0, y1 = arena.exit_region
    x, y = pose[:, 0], pose[:, 1]
    inside = np.flatnonzero((x >= x0) & (x <= x1) & (y >= y0) & (y <= y1))
    return int(inside[0]) if len(inside) else None


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


def avoidance_episodes(outputs: np.ndarray, pose: np.ndarray, *, threshold: float = 1.0,
                       max_gap: int = 5) -> list[dict]:  # fmt: skip
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
        episodes.append({"start": start, "end": end, "direction": direction,
                         "turn_deg": float(np.degrees(yaw[end] - yaw[max(start - 1, 0)]))})  # fmt: skip
        k = end + 1
    return episodes
