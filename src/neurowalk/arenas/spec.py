"""Arena descriptions: boxes on a flat floor, a start pose, the free area and an exit region.

An :class:`ArenaSpec` is a concrete, hashable layout (SI units, angles in rad). It writes the MJCF
elements that the robot's model places in its world body, and serves the 2-D geometry used by
metrics and the planar surrogate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

WALL_HEIGHT = 0.20
"""Height (m) of walls and avoidance obstacles: above what the climbing controller treats as a step
(``BackboneParams.climbable`` = 0.12 m), so that they stay obstacles with climbing switched on. The
original simulation used 0.10 m; the robot's ultrasonic rays (about 0.04 m up) see both alike."""


@dataclass(frozen=True)
class Box:
    """A box standing on the floor.

    Attributes:
        x: centre along the arena's x axis, m.
        y: centre along its y axis, m.
        yaw: heading of the box's x side, rad (counter-clockwise from the x axis).
        sx: full length along the box's own x side, m.
        sy: full length along its y side, m.
        h: height, m (default a wall's, :data:`WALL_HEIGHT`; lower boxes are steps a climbing robot can take).
    """

    x: float
    y: float
    yaw: float
    sx: float
    sy: float
    h: float = WALL_HEIGHT

    def __post_init__(self) -> None:
        if not all(math.isfinite(v) for v in (self.x, self.y, self.yaw, self.sx, self.sy, self.h)):
            raise ValueError(f"box values must be finite, got {self}")
        if min(self.sx, self.sy, self.h) <= 0:
            raise ValueError(f"box sizes must be > 0, got sx={self.sx}, sy={self.sy}, h={self.h}")

    def corners(self) -> np.ndarray:
        """(4, 2) corners of the footprint in the world frame (m), counter-clockwise."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        local = np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]]) * [self.sx / 2, self.sy / 2]
        return local @ np.array([[c, s], [-s, c]]) + [self.x, self.y]

    def contains(self, points: np.ndarray, margin: float = 0.0) -> np.ndarray:
        """Whether each of (n, 2) points lies inside the footprint grown by ``margin`` (m)."""
        pts = np.atleast_2d(points)
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        if pts.shape == (1, 2):  # one point (a start, a candidate box): the same arithmetic on floats, faster
            px, py = float(pts[0, 0]) - self.x, float(pts[0, 1]) - self.y
            u1, v1 = px * c + py * s, -px * s + py * c
            return np.array([abs(u1) <= self.sx / 2 + margin and abs(v1) <= self.sy / 2 + margin])
        p = pts - [self.x, self.y]
        u = p[:, 0] * c + p[:, 1] * s
        v = -p[:, 0] * s + p[:, 1] * c
        return (np.abs(u) <= self.sx / 2 + margin) & (np.abs(v) <= self.sy / 2 + margin)


def box_geom(name: str, half: tuple[float, float, float], pos: tuple[float, float, float], yaw: float) -> str:
    """One obstacle box as an MJCF ``<geom>``: half sizes (m), centre (m) and yaw (rad), with the one look and
    contact setting every obstacle has (friction 0.4, opaque: rays see it)."""
    hx, hy, hz = half
    return (
        f'    <geom name="{name}" type="box" size="{hx:.6g} {hy:.6g} {hz:.6g}" pos="{pos[0]:.6g} {pos[1]:.6g} '
        f'{pos[2]:.6g}" euler="0 0 {yaw:.9g}" rgba="0.55 0.45 0.35 1" friction="0.4"/>'
    )


@dataclass(frozen=True, kw_only=True)
class ArenaSpec:
    """A concrete arena.

    Attributes:
        name: registry name.
        boxes: the obstacles (walls are long boxes).
        start: robot start pose (x m, y m, yaw rad).
        bounds: free area (xmin, xmax, ymin, ymax) in m, or None for an unbounded floor.
        exit_region: (xmin, xmax, ymin, ymax) in m that counts as escaped, or None.
        exit_words: what reaching the exit region means, and not reaching it, in words (a run's line says them):
            ``("escaped", "did not escape")`` for a dead end, ``("climbed", "did not climb")`` for a step.
        options: the options it was built with (for the record).
    """

    name: str
    boxes: tuple[Box, ...] = ()
    start: tuple[float, float, float] = (0.0, 0.0, 0.0)
    bounds: tuple[float, float, float, float] | None = None
    exit_region: tuple[float, float, float, float] | None = None
    exit_words: tuple[str, str] = ("escaped", "did not escape")
    options: dict = field(default_factory=dict, compare=False, hash=False)

    ROBOT_RADIUS = 0.25  # m: start must be at least this far from every box

    def __post_init__(self) -> None:
        start = np.array(self.start[:2])
        for b in self.boxes:
            if b.contains(start, margin=self.ROBOT_RADIUS)[0]:
                raise ValueError(f"arena {self.name!r}: the start {self.start[:2]} overlaps the box at ({b.x}, {b.y})")

    def to_mjcf(self) -> str:
        """MJCF ``<geom>`` elements of the boxes (:func:`box_geom`)."""
        return "\n".join(
            box_geom(f"obstacle_{i}", (b.sx / 2, b.sy / 2, b.h / 2), (b.x, b.y, b.h / 2), b.yaw)
            for i, b in enumerate(self.boxes)
        )

    def free_cells(self, cell: float = 0.25) -> np.ndarray:
        """(n, 2) centres of the ``cell``-sized grid cells of the free area not covered by a box."""
        if self.bounds is None:
            raise ValueError(f"arena {self.name!r} is unbounded: it has no free cells")
        x0, x1, y0, y1 = self.bounds
        xs = np.arange(x0 + cell / 2, x1, cell)
        ys = np.arange(y0 + cell / 2, y1, cell)
        pts = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
        covered = np.zeros(len(pts), dtype=bool)
        for b in self.boxes:
            covered |= b.contains(pts)
        return pts[~covered]
