"""Climbing arenas: a single step (for height sweeps) and the paper's Fig. 10 track.

Steps and platforms are boxes standing on the floor (a platform of height h is a box h high);
walls are :data:`~neurowalk.arenas.spec.WALL_HEIGHT` (0.20 m) above whatever they stand on, so the
climbing controller (steps up to 0.12 m) sees them as walls. The robot starts at the origin facing +x.
"""

from __future__ import annotations

import math

from neurowalk.arenas import arena
from neurowalk.arenas.deadlocks import WALL
from neurowalk.arenas.spec import WALL_HEIGHT, ArenaSpec, Box

MAX_STEP = 0.25  # m, highest step these arenas build (the robot's legs reach about 0.17 m)
SLAB = 3.0  # m, depth of the single step's platform

# climbing-track corridors (m): the first runs along +x, the second along +y from its end.
HALF_WIDTH = 0.6  # half width of the first corridor
TRACK_END = 3.2  # x of the first corridor's end wall
BEND_X = 2.0  # x of the second corridor's left wall
FIRST_EDGE = 0.7  # x of the first platform's edge
SECOND_EDGE = 1.7  # y of the second platform's edge
TRACK_TOP = 4.4  # y of the second corridor's end wall
BACK = -0.6  # x of the wall behind the start
CLIMB_WORDS = ("climbed", "did not climb")  # the exit region of these arenas is a platform: reaching it is climbing


def _check_height(name: str, key: str, h: float) -> None:
    if not 0.0 < h <= MAX_STEP:
        raise ValueError(f"arena {name!r}: {key} must be in (0, {MAX_STEP}] m, got {h}")


@arena("steps")
def single_step(height: float = 0.06, distance: float = 0.5) -> ArenaSpec:
    """One step across the robot's path: a 3 x 3 m platform ``height`` (m) high, its edge ``distance`` (m) ahead.

    The exit region is the platform beyond 0.3 m from its edge: reaching it means the robot climbed up.
    """
    _check_height("steps", "height", height)
    if distance <= ArenaSpec.ROBOT_RADIUS:
        raise ValueError(f"arena 'steps': distance must be > {ArenaSpec.ROBOT_RADIUS} m, got {distance}")
    slab = Box(x=distance + SLAB / 2, y=0.0, yaw=0.0, sx=SLAB, sy=SLAB, h=height)
    exit_region = (distance + 0.3, distance + SLAB, -SLAB / 2, SLAB / 2)
    return ArenaSpec(name="steps", boxes=(slab,), exit_region=exit_region, exit_words=CLIMB_WORDS)


def _span(x0: float, x1: float, y0: float, y1: float, h: float) -> Box:
    """An axis-aligned box over [x0, x1] x [y0, y1], ``h`` high."""
    return Box(x=(x0 + x1) / 2, y=(y0 + y1) / 2, yaw=0.0, sx=x1 - x0, sy=y1 - y0, h=h)


def track_regions(step: float) -> dict[str, tuple[float, float, float, float, float]]:
    """Regions of the climbing track: name -> (xmin, xmax, ymin, ymax, floor height in m)."""
    return {
        "ground": (BACK, FIRST_EDGE, -HALF_WIDTH, HALF_WIDTH, 0.0),
        "first platform": (FIRST_EDGE, TRACK_END, -HALF_WIDTH, SECOND_EDGE, step),
        "second platform": (BEND_X, TRACK_END, SECOND_EDGE, TRACK_TOP, 2 * step),
    }


@arena("climbing-track")
def climbing_track(step: float = 0.06, wall_x: float = 2.0) -> ArenaSpec:
    """The paper's Fig. 10 track: ground floor, a first platform with a wall on it, a higher second platform.

    A corridor 1.2 m wide runs along +x: ground floor, then the first platform (``step`` m high) from
    x = 0.7 m. On it a wall runs diagonally from (``wall_x``, -0.6) to the corridor's far corner
    (3.2, 0.6), facing the robot at about 45°, so that turning left is the way on. The corridor turns
    left (+y) there; 1 m further on, the second platform (2 x ``step`` high) fills it to its end.
    Every wall is 0.20 m above the floor it stands on. The exit region is the second platform beyond
    0.3 m from its edge.
    """
    _check_height("climbing-track", "step", step)
    if not FIRST_EDGE + 0.6 <= wall_x <= TRACK_END - 0.6:
        raise ValueError(
            f"arena 'climbing-track': wall_x must be in [{FIRST_EDGE + 0.6}, {TRACK_END - 0.6}] m, got {wall_x}"
        )
    w, top = WALL / 2, 2 * step + WALL_HEIGHT
    x0, x1, y0, y1 = BACK, TRACK_END, -HALF_WIDTH, HALF_WIDTH
    boxes = [
        _span(FIRST_EDGE, x1, y0, SECOND_EDGE, step),  # first platform, including the bend
        _span(BEND_X, x1, SECOND_EDGE, TRACK_TOP, 2 * step),  # second platform
        _span(x0 - WALL, x0, y0 - WALL, y1 + WALL, top),  # behind the start
        _span(x0 - WALL, x1 + WALL, y0 - WALL, y0, top),  # right side of the first corridor
        _span(x0 - WALL, BEND_X, y1, y1 + WALL, top),  # left side, up to the bend
        _span(x1, x1 + WALL, y0 - WALL, TRACK_TOP + WALL, top),  # far end, then right side of the second
        _span(BEND_X - WALL, BEND_X, y1, TRACK_TOP + WALL, top),  # left side of the second corridor
        _span(BEND_X - WALL, x1 + WALL, TRACK_TOP, TRACK_TOP + WALL, top),  # end of the second corridor
    ]
    dx, dy = x1 - wall_x, y1 - y0
    length = math.hypot(dx, dy)
    boxes.append(Box(x=(wall_x + x1) / 2 - w, y=0.0, yaw=math.atan2(dy, dx), sx=length, sy=WALL, h=top))
    return ArenaSpec(
        name="climbing-track",
        boxes=tuple(boxes),
        bounds=(x0, x1, y0, TRACK_TOP),
        exit_region=(BEND_X, x1, SECOND_EDGE + 0.3, TRACK_TOP),
        exit_words=CLIMB_WORDS,
    )
