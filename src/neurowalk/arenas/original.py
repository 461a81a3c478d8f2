"""The authors' 9 x 9 m arena with 1 x 1 m boxes (reference/original_code_facts.md §8).

``cluttered``: the surrounding walls and the first set of boxes without the two, (6, -2) and
(5, -3), that close a sharp pocket with (5, -1) right ahead of the start: 9 boxes, obstacles but
no sharp corners or narrow passages (paper Fig. 3F). ``difficult``: both sets, 22 boxes, the original's
default arena: sharp corners and narrow passages (paper Fig. 3G, 5F). Boxes are 0.10 m high as in the
original (option ``height``; with climbing on they are steps), their yaw a multiple of 1 rad.
The robot starts at (3, -1) facing -0.38 rad, as in the original.
"""

from __future__ import annotations

from neurowalk.arenas import arena
from neurowalk.arenas.spec import ArenaSpec, Box

_WALLS = ((10, 1, 3, 5), (10, 1, 3, -5), (1, 10, -2, 0), (1, 10, 8, 0))  # (sx, sy, x, y)
_BASIC = (
    (0, 0, 3),
    (1, 1, 2),
    (2, 2, 4),
    (3, -2, 2),
    (5, -1, 1),
    (6, -2, 1),
    (4, 2, 5),
    (5, -3, 3),
    (3, 4, 0),
    (7, 0.5, 0),
    (-1, -4, 0),
)
_DIFFICULT = (
    (0, 3, 3),
    (0, -2, 2),
    (-1.5, -2, 4),
    (1.5, -4, 2),
    (7, -4, 3),
    (3.2, 0, 2),
    (1.5, -1, 4),
    (5.2, 3.8, 3),
    (7, 4, 2),
    (5.8, 2, 2),
    (3.5, -4, 1),
)
_POCKET = ((6, -2), (5, -3))  # with (5, -1) they form a sharp corner ahead of the start
_ANGLE = 1.0  # rad per yaw unit
_HEIGHT = 0.10  # as in the original; with climbing on, pass height=0.2 (0.10 m boxes are steps then)
_BOUNDS = (-1.5, 7.5, -4.5, 4.5)
_START = (3.0, -1.0, -0.38)


def _arena(name: str, boxes: tuple, height: float) -> ArenaSpec:
    if not height > 0:
        raise ValueError(f"arena {name!r}: height must be > 0 m, got {height}")
    walls = tuple(Box(x=x, y=y, yaw=0.0, sx=sx, sy=sy, h=height) for sx, sy, x, y in _WALLS)
    obstacles = tuple(Box(x=x, y=y, yaw=k * _ANGLE, sx=1.0, sy=1.0, h=height) for x, y, k in boxes)
    return ArenaSpec(name=name, boxes=walls + obstacles, start=_START, bounds=_BOUNDS)


@arena("cluttered")
def cluttered(height: float = _HEIGHT) -> ArenaSpec:
    """The original 9 x 9 m arena with 9 of its boxes: obstacles, no sharp corners. Option ``height`` (m)."""
    return _arena("cluttered", tuple(b for b in _BASIC if b[:2] not in _POCKET), height)


@arena("difficult")
def difficult(height: float = _HEIGHT) -> ArenaSpec:
    """The original 9 x 9 m arena with 22 boxes: sharp corners, narrow passages. Option ``height`` (m)."""
    return _arena("difficult", _BASIC + _DIFFICULT, height)
