"""Confined spaces and traps met on a path through a box arena: the outcome classes of paper Fig. 6.

The paper marks each of Fig. 6's environments: red, failed; green, a success "where the agent was facing to a
confined space"; blue, a success where it faced "a trap" ("Very small confined spaces can pose a problem for the
agent to escape because it is barely/not able to turn ... the agent can successfully escape if the confined space is
a bit bigger than in the fail case (green) or even there is a trap (blue)"). It gives no geometric definition;
:data:`CLASS_RULE` is the one used here, from the arena's boxes and the trunk's path alone:

- at each sampled point of the path, rays every 5 degrees over 360 degrees measure the distance to the nearest box
  (walls are boxes);
- a *trap* point: at least :data:`TRAP_BLOCKED_DEG` = 270 degrees of the directions meet a box within
  :data:`TRAP_REACH_M` = 0.6 m (a pocket closed on three sides, as the U-shaped dead end of paper Fig. 3A; a plain
  90-degree corner blocks about 210 degrees at 0.3 m from both walls and is no trap);
- a *confined* point (and no trap point): a box within :data:`SIDE_REACH_M` = 0.5 m on both sides (some ray within
  30 degrees of each side's normal, left and right of the trunk's heading) while the front and the back (rays
  within 20 degrees of the heading and of its reverse) are open beyond :data:`FRONT_OPEN_M` = 0.5 m: a passage at
  most about 1 m wide (three of the robot's 0.33 m turning radii) walked along, not a corner (a corner closes the
  front or the back);
- such a point was *left* when the trunk later came :data:`LEAVE_M` = 1 m or more away from it.

A run's class (:func:`classify`): "failed" where the run failed; else "escaped a trap" where it left a trap
point; else "passed a confined space" where it left a confined point; else "plain success". Failed runs also get
the situation they ended in (``end_situation``: "trap", "confined space" or "open", from the points of the last
300 s).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from neurowalk.arenas import ArenaSpec

RAYS = 72  # directions, every 5 degrees
TRAP_REACH_M = 0.6
TRAP_BLOCKED_DEG = 270.0
SIDE_REACH_M = 0.5
SIDE_SECTOR_DEG = 30.0  # half-width of each side's sector around the heading's normal
FRONT_OPEN_M = 0.5
FRONT_SECTOR_DEG = 20.0  # half-width of the front and back sectors around the heading and its reverse
LEAVE_M = 1.0
CLASSES = ("failed", "passed a confined space", "escaped a trap", "plain success")
#: The rule's numbers, for the json.
RULE_NUMBERS: dict[str, float] = {
    "rays": RAYS,
    "trap_reach_m": TRAP_REACH_M,
    "trap_blocked_deg": TRAP_BLOCKED_DEG,
    "side_reach_m": SIDE_REACH_M,
    "side_sector_deg": SIDE_SECTOR_DEG,
    "front_open_m": FRONT_OPEN_M,
    "front_sector_deg": FRONT_SECTOR_DEG,
    "leave_m": LEAVE_M,
}
CLASS_RULE = (
    f"rays every {360 / RAYS:g} deg from the trunk centre; trap: >= {TRAP_BLOCKED_DEG:g} deg of them meet a box "
    f"within {TRAP_REACH_M:g} m; confined space: a box within {SIDE_REACH_M:g} m on both sides "
    f"(±{SIDE_SECTOR_DEG:g} deg about each side of the heading), front and back (±{FRONT_SECTOR_DEG:g} deg) open "
    f"beyond {FRONT_OPEN_M:g} m; faced and left: the trunk later came >= {LEAVE_M:g} m away. Blue: success that left a "
    "trap; green: success that left a confined space (no trap); red: failed; unframed: success, neither faced"
)


def ray_distances(
    boxes: tuple[Any, ...] | list[Any], points: np.ndarray, angles: np.ndarray, max_range: float
) -> np.ndarray:
    """(P, D) distance (m) from each of ``points`` (P, 2) along each world direction ``angles`` (D,) rad to the
    nearest of ``boxes`` (:class:`~neurowalk.arenas.spec.Box`), ``inf`` beyond ``max_range``; 0 inside a box."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    dx, dy = np.cos(angles), np.sin(angles)
    best = np.full((len(pts), len(dx)), np.inf)
    for b in boxes:
        hx, hy = b.sx / 2, b.sy / 2
        near = np.hypot(pts[:, 0] - b.x, pts[:, 1] - b.y) <= max_range + math.hypot(hx, hy)
        if not near.any():
            continue
        c, s = math.cos(b.yaw), math.sin(b.yaw)
        rx, ry = pts[near, 0] - b.x, pts[near, 1] - b.y
        px, py = (c * rx + s * ry)[:, None], (-s * rx + c * ry)[:, None]  # the points in the box's frame
        ux, uy = c * dx + s * dy, -s * dx + c * dy  # the directions in the box's frame
        ux = np.where(np.abs(ux) < 1e-12, 1e-12, ux)[None, :]  # a ray parallel to a slab: far crossings
        uy = np.where(np.abs(uy) < 1e-12, 1e-12, uy)[None, :]
        ax, bx = (-hx - px) / ux, (hx - px) / ux
        ay, by = (-hy - py) / uy, (hy - py) / uy
        t0 = np.maximum(np.minimum(ax, bx), np.minimum(ay, by))
        t1 = np.minimum(np.maximum(ax, bx), np.maximum(ay, by))
        t = np.where((t0 <= t1) & (t1 >= 0.0), np.maximum(t0, 0.0), np.inf)
        best[near] = np.minimum(best[near], t)
    best[best > max_range] = np.inf
    return best


def situations(arena: ArenaSpec, pose: np.ndarray, trap_deg: float = TRAP_BLOCKED_DEG) -> dict[str, np.ndarray]:
    """Per row of ``pose`` (P, 3: x m, y m, yaw rad): ``blocked_deg`` (directions meeting a box within
    :data:`TRAP_REACH_M`, degrees), ``trap`` (at least ``trap_deg`` of them) and ``confined`` (bool, by
    :data:`CLASS_RULE`)."""
    pose = np.asarray(pose, dtype=float).reshape(-1, 3)
    angles = np.arange(RAYS) * (2 * math.pi / RAYS)
    reach = max(TRAP_REACH_M, SIDE_REACH_M, FRONT_OPEN_M)
    d = ray_distances(arena.boxes, pose[:, :2], angles, reach)
    blocked_deg = np.count_nonzero(d <= TRAP_REACH_M, axis=1) * (360.0 / RAYS)
    trap = blocked_deg >= trap_deg
    rel = np.degrees(np.angle(np.exp(1j * (angles[None, :] - pose[:, 2:3]))))  # (P, D) in (-180, 180]

    def nearest(centre: float, half: float) -> np.ndarray:
        off = np.abs((rel - centre + 180.0) % 360.0 - 180.0)
        return np.where(off <= half + 1e-9, d, np.inf).min(axis=1)

    left, right = nearest(90.0, SIDE_SECTOR_DEG), nearest(-90.0, SIDE_SECTOR_DEG)
    front, back = nearest(0.0, FRONT_SECTOR_DEG), nearest(180.0, FRONT_SECTOR_DEG)
    sides = (left <= SIDE_REACH_M) & (right <= SIDE_REACH_M)
    confined = sides & (front > FRONT_OPEN_M) & (back > FRONT_OPEN_M) & ~trap
    return {"blocked_deg": blocked_deg, "trap": trap, "confined": confined}


def first_left(xy: np.ndarray, mask: np.ndarray, leave_m: float = LEAVE_M) -> int | None:
    """The first row i with ``mask[i]`` that the path later left: some row j > i lies ``leave_m`` or more from
    row i (``xy`` (P, 2) m); None if there is none."""
    xy = np.asarray(xy, dtype=float)
    rows = np.flatnonzero(mask)
    for k in range(0, len(rows), 256):
        chunk = rows[k : k + 256]
        far = np.hypot(xy[None, :, 0] - xy[chunk, None, 0], xy[None, :, 1] - xy[chunk, None, 1]) >= leave_m
        far &= np.arange(len(xy))[None, :] > chunk[:, None]
        hit = np.flatnonzero(far.any(axis=1))
        if len(hit):
            return int(chunk[hit[0]])
    return None


def classify(
    arena: ArenaSpec,
    pose: np.ndarray,
    success: bool,
    *,
    end_rows: int | None = None,
    trap_deg: float = TRAP_BLOCKED_DEG,
) -> dict[str, Any]:
    """A run's Fig. 6 class from its ``arena``, its trunk ``pose`` (P, 3, any sampling) and whether it succeeded.

    Returns ``class`` (one of :data:`CLASSES`), ``faced_trap``, ``faced_confined`` (some such point on the path),
    ``left_trap``, ``left_confined`` (the first such point it left: [x, y] m, or None), the widest blocked angle
    met (``max_blocked_deg``), and ``end_situation`` ("trap", "confined space", "open") over the last
    ``end_rows`` rows (default: all rows). ``trap_deg``: the blocked angle of a trap point (degrees).
    """
    pose = np.asarray(pose, dtype=float).reshape(-1, 3)
    sit = situations(arena, pose, trap_deg)
    xy = pose[:, :2]
    i_trap, i_conf = first_left(xy, sit["trap"]), first_left(xy, sit["confined"])
    if not success:
        cls = "failed"
    elif i_trap is not None:
        cls = "escaped a trap"
    elif i_conf is not None:
        cls = "passed a confined space"
    else:
        cls = "plain success"
    tail = slice(-end_rows if end_rows else 0, None)
    end = "trap" if sit["trap"][tail].any() else "confined space" if sit["confined"][tail].any() else "open"
    return {
        "class": cls,
        "faced_trap": bool(sit["trap"].any()),
        "faced_confined": bool(sit["confined"].any()),
        "left_trap": None if i_trap is None else xy[i_trap].tolist(),
        "left_confined": None if i_conf is None else xy[i_conf].tolist(),
        "max_blocked_deg": float(sit["blocked_deg"].max()) if len(pose) else 0.0,
        "end_situation": end,
    }
