"""Behaviour metrics: pure functions of a trajectory's arrays (poses in m and rad, one row per step)."""

from __future__ import annotations

import math

import numpy as np

from neurowalk import metrics_kernel
from neurowalk.arenas.spec import ArenaSpec


def path_length(pose: np.ndarray) -> float:
    """Length (m) of the trunk centre's path, pose (T, 3)."""
    return float(np.sum(metrics_kernel.step_lengths(_xy(pose))))


def heading_change(pose: np.ndarray, start_yaw: float | None = None) -> float:
    """Net change of heading (rad, counter-clockwise positive), unwrapped over the whole path."""
    yaw = metrics_kernel.unwrap(np.concatenate([[pose[0, 2] if start_yaw is None else start_yaw], pose[:, 2]]))
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
    then got out counts here. The stretches start at 0, ``stride``, ... and at ``T - window``; a compiled pass
    (:func:`neurowalk.metrics_kernel.ever_fits`) decides them, numpy the exact ties.
    """
    if window < 1 or stride < 1:
        raise ValueError(f"need window >= 1 and stride >= 1, got {window}, {stride}")
    found, undecided = metrics_kernel.ever_fits(_xy(pose), int(window), float(radius), int(stride))
    return bool(found) or any(_stretch_fits(pose[:, :2], int(s), window, radius) for s in undecided)


def _xy(pose: np.ndarray) -> np.ndarray:
    """(T, 2) float64 view (a copy if ``pose`` is not float64) of the positions (m) of ``pose`` (T, >= 2)."""
    return np.asarray(pose, dtype=np.float64)[:, :2]


def _stretch_fits(xy: np.ndarray, s: int, window: int, radius: float) -> bool:
    """Whether rows [s, s + window) of ``xy`` (T, 2) all lie within ``radius`` (m) of their mean, by numpy."""
    seg = xy[s : s + window]
    return bool(np.max(np.sum((seg - seg.mean(axis=0)) ** 2, axis=1)) <= radius * radius)


def coverage(pose: np.ndarray, arena: ArenaSpec, cell: float = 0.25) -> float | None:
    """Fraction of the arena's free ``cell``-sized cells the trunk centre visited (None if unbounded)."""
    if arena.bounds is None:
        return None
    free = arena.free_cells(cell)
    if len(free) == 0:
        return None
    x0, _, y0, _ = arena.bounds
    keys = np.floor((free - [x0, y0]) / cell).astype(np.int64)
    hits = metrics_kernel.visited_count(_xy(pose), float(x0), float(y0), float(cell), keys)
    return hits / len(free)


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
    if outputs.dtype == np.float64 and outputs.ndim == 2:
        return metrics_kernel.turn_state(outputs, float(threshold))
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
    runs = metrics_kernel.turn_runs(turn_state(outputs, threshold).astype(np.int64), int(max_gap))
    if len(runs) == 0:
        return []
    yaw = metrics_kernel.unwrap(np.ascontiguousarray(pose[:, 2], dtype=np.float64))
    turn = np.degrees(yaw[runs[:, 1]] - yaw[np.maximum(runs[:, 0] - 1, 0)])
    return [
        {"start": int(a), "end": int(b), "direction": int(d), "turn_deg": float(deg)}
        for (a, b, d), deg in zip(runs.tolist(), turn.tolist(), strict=True)
    ]


WEDGE_RADIUS = 0.3
"""Radius (m) of the disc a wedged robot's trunk centre stays in: the legs' reach (about 0.25 m) plus a little."""
WEDGE_MIN_S = 100.0
"""Shortest wedged period (s): 1000 control steps at 10 Hz, longer than any avoidance turn in the open."""
BLIND_M = 0.38
"""Ultrasonic reading (m) from which a ray counts as blind: no echo, or an echo no nearer than the sensor noise
reaches with nothing in range (0.40 m range, noise std about 3 mm there)."""
WEDGE_CAUSES = ("both rays blind", "body contact", "other")


HELD_HEADING_DEG = 30.0
"""Widest range (degrees) of the heading over a wedged stretch in which the robot counts as *held*, not turning:
a robot pressed against an obstacle with its legs still stepping yaws a little; one turning in place at 1-2 deg/s
sweeps 100-200 degrees in :data:`WEDGE_MIN_S`."""


def _fitting_starts(xy: np.ndarray, window: int, radius: float, stride: int) -> np.ndarray:
    """(k,) int64 ascending starts of the ``window``-row stretches (started every ``stride`` rows, and at the end)
    whose positions, rows of ``xy`` (T, 2) in m, all lie within ``radius`` (m) of their mean.

    Cheap bounds first, from the extremes of blocks of ``stride`` rows: a stretch whose whole blocks span more
    than the disc's diameter in x or y cannot fit; one whose covering blocks' bounding box lies within the disc
    around the stretch's mean fits. Only the stretches in between are checked point by point. A compiled pass
    (:func:`neurowalk.metrics_kernel.fitting_starts`) does all of it; numpy checks the exact ties, 256
    stretches at a time.
    """
    n = len(xy)
    if n >= window and n // stride < -(-(n - window) // stride):  # the last stretch holds no block boundary
        raise ValueError(f"window ({window} rows) shorter than stride ({stride}): the blocks cannot bound it")
    fits, todo = metrics_kernel.fitting_starts(_xy(xy), int(window), float(radius), int(stride))
    if len(todo):
        views = np.lib.stride_tricks.sliding_window_view(xy, window, axis=0)  # (T - window + 1, 2, window)
        found = [fits]
        for k in range(0, len(todo), 256):
            chunk = views[todo[k : k + 256]]
            d2 = np.sum((chunk - chunk.mean(axis=2, keepdims=True)) ** 2, axis=1)
            found.append(todo[k : k + 256][np.max(d2, axis=1) <= radius * radius])
        fits = np.sort(np.concatenate(found))
    return fits


def _fitting_windows(xy: np.ndarray, window: int, radius: float, stride: int) -> np.ndarray:
    """(T,) bool: rows of ``xy`` (T, 2) inside some stretch of :func:`_fitting_starts` (one that fits the disc)."""
    return metrics_kernel.mark_stretches(len(xy), _fitting_starts(xy, window, radius, stride), int(window))


def _runs(marked: np.ndarray) -> list[tuple[int, int]]:
    """The maximal runs of True in ``marked`` (T,) bool, as (first, stop) row pairs: rows [first, stop)."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], marked.astype(np.int8), [0]])))
    return [(int(s), int(e)) for s, e in zip(edges[::2], edges[1::2], strict=True)]


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
    heading_deg: float = HELD_HEADING_DEG,
) -> list[dict]:
    """Periods in which the robot stayed put: its trunk centre within a small disc for more than ``min_s`` s.

    A control step is wedged if it lies in a stretch of more than ``min_s`` seconds (started every ``stride``
    steps) whose trunk positions all lie within ``radius`` of their mean, as in :func:`trapped`; a period is a
    maximal run of wedged steps. Overlapping stretches join, so a period can outgrow the disc a little where
    the robot creeps (``extent_m`` says by how much).

    Held or turning. A slow avoidance turn stays in the disc too (at about 1 cm/s and 2 deg/s a turn of 90
    degrees takes over 100 s), so each stretch that fits the disc is also asked whether the robot's heading
    stayed within a band: the range (max minus min) of the unwrapped yaw over the stretch at most
    ``heading_deg``. A step is *held* if it lies in a stretch that fits both; the held steps' maximal runs are
    the period's ``held`` runs. The rule is asked of stretches, not of whole periods, because a period joins
    whatever overlapping stretches fit the disc: a robot held at a wall for 200 s that then turns away in place
    makes one period whose whole heading range is large, yet it was held for 200 s; one that turns for 300 s
    has no stretch of ``min_s`` within the band and no held step at all. Held steps are wedged steps, so each
    held run lies inside one period. A period with no held step is a *turning* one.

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
        heading_deg: widest heading range (degrees) of a held stretch, default :data:`HELD_HEADING_DEG` = 30.

    Returns:
        One dict per period, in time order: ``start``, ``end`` (first and last control step, inclusive),
        ``duration_s``, ``centre`` ([x, y] m, mean position), ``extent_m`` (largest distance from it),
        ``blind_fraction`` and ``contact_fraction`` (share of its steps with both rays blind / with body contact
        among those where it is known; None where not given), ``cause``: "both rays blind" when both rays
        were blind for more than half of it, else "body contact" when the body touched an obstacle for more than
        half of it, else "other"; ``heading_range_deg`` (range of the unwrapped yaw over the whole period,
        degrees), ``held`` ([first, last] control steps, inclusive, of each run of held steps in it; empty for a
        turning period) and ``held_s`` (s, its held steps in all).
    """
    if not control_hz > 0 or not radius > 0 or not min_s > 0 or stride < 1 or not heading_deg >= 0:
        raise ValueError(
            f"need control_hz, radius, min_s > 0, stride >= 1 and heading_deg >= 0, got {control_hz}, {radius}, "
            f"{min_s}, {stride}, {heading_deg}"
        )
    pose = np.asarray(pose, dtype=float)
    xy = pose[:, :2]
    window = math.floor(min_s * control_hz + 1e-9) + 1  # more than min_s seconds
    fits = _fitting_starts(xy, window, radius, stride)
    marked = metrics_kernel.mark_stretches(len(xy), fits, window)
    yaw = metrics_kernel.unwrap(np.ascontiguousarray(pose[:, 2]))
    narrow = metrics_kernel.heading_ranges(yaw, fits, window) <= math.radians(heading_deg)  # NaN: not held
    held = _runs(metrics_kernel.mark_stretches(len(xy), fits[narrow], window))
    if blind is None and us_distance is not None:
        blind = np.all(np.asarray(us_distance) >= blind_m, axis=1)
    touch = None if contact is None else np.asarray(contact, dtype=float)
    periods: list[dict] = []
    for s, e in _runs(marked):  # rows [s, e)
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
                "heading_range_deg": float(np.degrees(np.max(yaw[s:e]) - np.min(yaw[s:e]))),
                "held": [[a, b - 1] for a, b in held if s <= a < e],  # held runs lie within one period
                "held_s": float(sum(b - a for a, b in held if s <= a < e) / control_hz),
            }
        )
    return periods


def held_periods(periods: list[dict], control_hz: float = 10.0) -> list[dict]:
    """The held runs of :func:`wedged_periods`' ``periods``, flat and in time order: ``start``, ``end`` (control
    steps, inclusive), ``duration_s`` (at ``control_hz`` steps per second) and the ``cause`` of the wedged period
    each lies in."""
    return [
        {"start": a, "end": b, "duration_s": (b - a + 1) / control_hz, "cause": p["cause"]}
        for p in periods
        for a, b in p["held"]
    ]


def wedged_summary(periods: list[dict], control_hz: float = 10.0) -> dict:
    """Counts of :func:`wedged_periods`: ``wedged_periods`` (number), ``longest_wedged_s``, ``wedged_causes``;
    ``held_periods`` (number of held runs, :func:`held_periods`), ``longest_held_s`` (s) and ``turning_periods``
    (wedged periods with no held step), at ``control_hz`` steps per second."""
    causes: dict[str, int] = {}
    for p in periods:
        causes[p["cause"]] = causes.get(p["cause"], 0) + 1
    held = held_periods(periods, control_hz)
    return {
        "wedged_periods": len(periods),
        "longest_wedged_s": max((p["duration_s"] for p in periods), default=0.0),
        "wedged_causes": causes,
        "held_periods": len(held),
        "longest_held_s": max((h["duration_s"] for h in held), default=0.0),
        "turning_periods": sum(1 for p in periods if not p["held"]),
    }
