"""Arenas with more structure: the complex path of paper Fig. 9, and random box fields (Fig. 6, Table 2)."""

from __future__ import annotations

import math

import numpy as np

from neurowalk.arenas import arena
from neurowalk.arenas.deadlocks import HEIGHT, WALL, _wall
from neurowalk.arenas.spec import ArenaSpec, Box


@arena("complex-path")
def complex_path(length: float = 4.0, width: float = 1.2, obstacle: float = 0.2) -> ArenaSpec:
    """A path with a wall on the right, small obstacles on the left and a dead end (paper Fig. 9).

    The robot enters at the origin facing +x. The right wall runs the whole ``length`` (m); small
    boxes of side ``obstacle`` (m) line the left side, ``width`` (m) from the right wall, with gaps
    the robot can see through but is meant to avoid; the path ends in a closed corner. It has
    left the path when its trunk centre is beyond the left row of obstacles.
    """
    if length < 2.0:
        raise ValueError(f"arena 'complex-path': length must be >= 2 m, got {length}")
    if not 0.6 <= width <= 3.0:
        raise ValueError(f"arena 'complex-path': width must be in [0.6, 3] m, got {width}")
    if not 0.05 <= obstacle <= 0.5:
        raise ValueError(f"arena 'complex-path': obstacle must be in [0.05, 0.5] m, got {obstacle}")
    y_right = -0.45
    y_left = y_right + width
    boxes = [_wall(-0.5, y_right - WALL / 2, length, y_right - WALL / 2),
             _wall(length + WALL / 2, y_right - WALL, length + WALL / 2, y_left + 0.6)]  # fmt: skip
    for x in np.arange(0.6, length - 0.6, 0.7):
        boxes.append(Box(x=float(x), y=y_left + obstacle / 2, yaw=0.0, sx=obstacle, sy=obstacle, h=HEIGHT))
    exit_region = (-1.0, length + 1.0, y_left + obstacle + 0.3, y_left + 5.0)
    return ArenaSpec(name="complex-path", boxes=tuple(boxes), exit_region=exit_region,
                     bounds=(-0.5, length, y_right, y_left + 1.5))  # fmt: skip


@arena("random")
def random_boxes(n_boxes: int = 10, size: float = 0.6, extent: float = 6.0,
                 rng: np.random.Generator | None = None) -> ArenaSpec:  # fmt: skip
    """Surrounding walls around an ``extent`` x ``extent`` m field of ``n_boxes`` boxes of side ``size`` (m).

    Positions and yaws are drawn from the run's Generator; no box comes within reach of the start
    (the centre, facing a random direction).
    """
    if not 0 <= n_boxes <= 60:
        raise ValueError(f"arena 'random': n_boxes must be in [0, 60], got {n_boxes}")
    if not 0.1 <= size <= 2.0:
        raise ValueError(f"arena 'random': size must be in [0.1, 2] m, got {size}")
    if not 2.0 <= extent <= 30.0:
        raise ValueError(f"arena 'random': extent must be in [2, 30] m, got {extent}")
    rng = rng if rng is not None else np.random.default_rng(0)
    h = extent / 2
    e = h + WALL / 2  # centre line of the surrounding walls
    walls = (_wall(-h, e, h, e), _wall(-h, -e, h, -e), _wall(-e, -e, -e, e), _wall(e, -e, e, e))
    keep_out = ArenaSpec.ROBOT_RADIUS + 0.25  # m of free floor around the start
    boxes: list[Box] = []
    for _ in range(1000 * max(n_boxes, 1)):
        if len(boxes) == n_boxes:
            break
        x, y = rng.uniform(-h + size / 2, h - size / 2, size=2)
        b = Box(x=float(x), y=float(y), yaw=float(rng.uniform(0, math.pi / 2)), sx=size, sy=size, h=HEIGHT)
        if not b.contains(np.zeros((1, 2)), margin=keep_out)[0]:
            boxes.append(b)
    if len(boxes) < n_boxes:
        raise ValueError(f"arena 'random': cannot place {n_boxes} boxes of {size} m in {extent} m")
    start = (0.0, 0.0, float(rng.uniform(-math.pi, math.pi)))
    return ArenaSpec(name="random", boxes=walls + tuple(boxes), start=start, bounds=(-h, h, -h, h))
