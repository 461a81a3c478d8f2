"""Basic arenas: the open floor and a single box ahead (for steering and avoidance checks)."""

from __future__ import annotations

import math

from neurowalk.arenas import arena
from neurowalk.arenas.spec import WALL_HEIGHT, ArenaSpec, Box


@arena("open")
def open_floor() -> ArenaSpec:
    """Flat, unbounded floor; the robot starts at the origin facing +x."""
    return ArenaSpec(name="open")


@arena("box")
def box_ahead(
    distance: float = 1.0, offset: float = 0.0, width: float = 1.0, angle: float = 0.0, height: float = WALL_HEIGHT
) -> ArenaSpec:
    """One box ahead of the robot.

    Options: ``distance`` (m) from the start to the box's near face, ``offset`` (m) of its centre to
    the left (+) or right (-), ``width`` (m) across the path, ``angle`` (deg) of its yaw, ``height`` (m).
    """
    if distance <= ArenaSpec.ROBOT_RADIUS:
        raise ValueError(f"arena 'box': distance must be > {ArenaSpec.ROBOT_RADIUS} m, got {distance}")
    if width <= 0 or height <= 0:
        raise ValueError(f"arena 'box': width and height must be > 0, got width={width}, height={height}")
    depth = 0.2
    b = Box(x=distance + depth / 2, y=offset, yaw=math.radians(angle), sx=depth, sy=width, h=height)
    return ArenaSpec(name="box", boxes=(b,))
