"""Dead ends: the simple deadlock, the narrow passage and the sharp corner (paper Fig. 3A-B, 5A-B).

The robot starts at the origin facing +x, inside the trap. Walls are 0.20 m high boxes (``WALL_HEIGHT``), 0.10 m
thick. The exit region lies behind the start, outside the trap's mouth: reaching it means the robot
turned around and walked out.
"""

from __future__ import annotations

import math

from neurowalk.arenas import arena
from neurowalk.arenas.spec import WALL_HEIGHT, ArenaSpec, Box

WALL = 0.10  # wall thickness (m)
HEIGHT = WALL_HEIGHT  # wall and box height (m); the original used 0.10
MOUTH_X = -0.5  # x of the trap's open end (m)
EXIT_MARGIN = 0.3  # the exit region starts this far outside the mouth (m)


def wall(x0: float, y0: float, x1: float, y1: float) -> Box:
    """A wall whose centre line runs from (x0, y0) to (x1, y1)."""
    length = math.hypot(x1 - x0, y1 - y0)
    return Box(x=(x0 + x1) / 2, y=(y0 + y1) / 2, yaw=math.atan2(y1 - y0, x1 - x0), sx=length, sy=WALL, h=HEIGHT)


def _dead_end(name: str, width: float, depth: float, gap: float, funnel: float) -> ArenaSpec:
    """Side walls from the mouth to the end; the end wall split by ``gap`` (0: closed).

    ``funnel`` (deg) tilts each side wall inward, so the end is narrower than the mouth.
    """
    if width <= 0.3:
        raise ValueError(f"arena {name!r}: width must be > 0.3 m (the robot must fit), got {width}")
    if depth <= 0.6:
        raise ValueError(f"arena {name!r}: depth must be > 0.6 m, got {depth}")
    if not 0 <= funnel < 60:
        raise ValueError(f"arena {name!r}: funnel angle must be in [0, 60) degrees, got {funnel}")
    x_end = MOUTH_X + depth
    half_end = width / 2 - depth * math.tan(math.radians(funnel))
    if half_end <= 0.15:
        raise ValueError(
            f"arena {name!r}: funnel {funnel}° closes the trap before its end (width {width}, depth {depth})"
        )
    if not 0 <= gap < 2 * half_end - 0.1:
        raise ValueError(f"arena {name!r}: gap must be in [0, {2 * half_end - 0.1:.2f}) m, got {gap}")
    boxes = [
        wall(MOUTH_X, width / 2 + WALL / 2, x_end, half_end + WALL / 2),
        wall(MOUTH_X, -width / 2 - WALL / 2, x_end, -half_end - WALL / 2),
    ]
    outer = half_end + WALL
    if gap == 0:
        boxes.append(wall(x_end + WALL / 2, -outer, x_end + WALL / 2, outer))
    else:
        boxes.append(wall(x_end + WALL / 2, gap / 2, x_end + WALL / 2, outer))
        boxes.append(wall(x_end + WALL / 2, -gap / 2, x_end + WALL / 2, -outer))
    reach = max(width, 2.0)
    exit_region = (MOUTH_X - 5.0, MOUTH_X - EXIT_MARGIN, -reach - 3.0, reach + 3.0)
    bounds = (MOUTH_X - 2.0, x_end + 0.5, -width / 2 - 1.5, width / 2 + 1.5)
    return ArenaSpec(name=name, boxes=tuple(boxes), bounds=bounds, exit_region=exit_region)


@arena("simple-deadlock")
def simple_deadlock(width: float = 1.0, depth: float = 1.5) -> ArenaSpec:
    """A U-shaped dead end the robot starts in, facing its closed end.

    Options: ``width`` (m) between the side walls, ``depth`` (m) from the mouth to the end wall.
    """
    return _dead_end("simple-deadlock", width, depth, 0.0, 0.0)


@arena("narrow-passage")
def narrow_passage(width: float = 1.6, depth: float = 1.5, gap: float = 0.28, funnel: float = 10.0) -> ArenaSpec:
    """A dead end whose end is two obstacles with a gap narrower than the robot, behind a funnel.

    Options: ``width`` (m) at the mouth, ``depth`` (m), ``gap`` (m) between the two end
    obstacles, ``funnel`` (deg) inward tilt of each side wall.
    """
    if gap <= 0:
        raise ValueError(f"arena 'narrow-passage': gap must be > 0 m, got {gap}")
    return _dead_end("narrow-passage", width, depth, gap, funnel)


@arena("corner")
def corner(angle: float = 60.0, length: float = 2.0) -> ArenaSpec:
    """A sharp corner: two walls meeting ahead of the robot at ``angle`` (deg), each ``length`` (m) long.

    The robot starts on the corner's bisector, 1 m from the apex, facing it.
    """
    if not 10 <= angle <= 170:
        raise ValueError(f"arena 'corner': angle must be in [10, 170] degrees, got {angle}")
    if length <= 0.5:
        raise ValueError(f"arena 'corner': length must be > 0.5 m, got {length}")
    apex = 1.0
    half = math.radians(angle) / 2
    boxes = []
    for side in (1, -1):
        d = (-math.cos(half), side * math.sin(half))  # along the wall, away from the apex
        n = (math.sin(half), side * math.cos(half))  # outward normal (away from the robot)
        x0, y0 = apex + n[0] * WALL / 2, n[1] * WALL / 2  # centre line: inner face through the apex
        boxes.append(wall(x0, y0, x0 + d[0] * length, y0 + d[1] * length))
    exit_d = 1.5
    exit_region = (-10.0, apex - length * math.cos(half) - exit_d, -10.0, 10.0)  # beyond the walls' ends
    return ArenaSpec(
        name="corner",
        boxes=tuple(boxes),
        exit_region=exit_region,
        bounds=(apex - length - 1.0, apex + 0.5, -length - 0.5, length + 0.5),
    )
