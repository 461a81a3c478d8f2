"""Padded AMOSII models: the same sizes for every arena of at most ``n_slots`` boxes, for ``mujoco.batch``.

``mujoco.batch.Batch.set_models`` runs each simulation on a model of its own as long as all of them give
``MjData`` the same layout (numbers of bodies, geoms, bounding-volume nodes, ...). The padded model of an arena
is its plain model (robot, floor, the arena's boxes as world geoms, in the same order) plus one static body,
``obstacle_parking``, 10 m below the floor, holding ``n_slots - n_boxes + 1`` small invisible boxes: so every
padded model of ``n_slots`` has the same sizes, whatever its arena (the parking body always holds at least one
box, so that it always has a bounding-volume tree).

A parked box can touch nothing: it is welded to the world (MuJoCo never collides two bodies welded together, so
not with the floor or the arena's boxes), far below the floor the robot stands on, and no sensor ray from the
robot reaches it before the floor. The parking body comes after the robot, so bodies, geoms and contacts keep
the plain model's ids and order: measured, a padded model gives the same trajectory, bit for bit, as the plain
one (tests/sim/test_batch.py), and costs about 2% of physics time.

Why not one model whose box geoms are moved per simulation (``Batch.expand("geom_pos")`` + ``set_const()``,
the other way ``mujoco.batch`` offers): that gives the same numbers, but the world body's bounding-volume tree
is built by the compiler for the boxes' compiled places and only its boxes are recomputed, so the midphase
prunes poorly: measured 13% slower physics on the ``random`` arena.
"""

from __future__ import annotations

import math

import numpy as np

from neurowalk.arenas.spec import ArenaSpec, box_geom

__all__ = ["PARKING_BODY", "PARK_Z", "padded_world", "slot_rows", "slot_world"]

PARKING_BODY = "obstacle_parking"
"""Name of the static body holding the parked boxes (geoms ``parked_0``, ``parked_1``, ...)."""
PARK_Z = -10.0
"""Height (m) of the parking body, far below the floor."""
_PARK_SIZE = 0.05  # m, half size of a parked box
_PARK_PITCH = 0.2  # m between parked boxes (side by side along x)


def padded_world(arena: ArenaSpec, n_slots: int) -> str:
    """The world-body MJCF of ``arena``'s padded model: its boxes, then the parking body.

    Args:
        arena: the arena.
        n_slots: most boxes of any arena that is to share the model's sizes (>= the arena's own box count).

    Returns:
        MJCF for ``amosii_xml(world=...)``.

    Raises:
        ValueError: if the arena has more than ``n_slots`` boxes.
    """
    n = _boxes_within(arena, n_slots)
    s = f"{_PARK_SIZE:g}"
    parked = [
        f'      <geom name="parked_{k}" type="box" size="{s} {s} {s}" pos="{k * _PARK_PITCH:.6g} 0 0" '
        f'rgba="0.55 0.45 0.35 0"/>'
        for k in range(n_slots - n + 1)
    ]
    body = f'    <body name="{PARKING_BODY}" pos="0 0 {PARK_Z:g}">'
    return "\n".join([arena.to_mjcf(), body, *parked, "    </body>"])


def slot_world(arena: ArenaSpec, n_slots: int) -> str:
    """The world-body MJCF of ``arena`` with exactly ``n_slots`` obstacle geoms, for one model of many worlds.

    The arena's boxes are geoms ``obstacle_0 ...``; the unused slots are more world boxes ``obstacle_n ...``
    at :data:`PARK_Z`, far below the floor. All are world geoms, so every arena of at most ``n_slots`` boxes gives
    a model of the same structure whose obstacle geoms differ only in ``geom_pos``, ``geom_quat``,
    ``geom_size``, ``geom_aabb`` and ``geom_rbound`` (:func:`slot_rows`): what MuJoCo Warp batches per world.
    Everything else of a slot is world 0's for every world, so a parked box is an obstacle like any other
    (:func:`~neurowalk.arenas.spec.box_geom`: opaque, friction 0.4), only small and out of reach: were it
    transparent, the rays of a world with a box in that slot would not see the box. (World geoms never collide
    with each other, and no ray of the robot reaches below the floor.)
    """
    n = _boxes_within(arena, n_slots)
    half = (_PARK_SIZE,) * 3
    parked = [box_geom(f"obstacle_{k}", half, ((k - n) * _PARK_PITCH, 0.0, PARK_Z), 0.0) for k in range(n, n_slots)]
    return "\n".join([arena.to_mjcf(), *parked])


def slot_rows(arena: ArenaSpec, n_slots: int) -> dict[str, np.ndarray]:
    """The obstacle geoms' rows of :func:`slot_world` (arena, n_slots), as MuJoCo compiles them.

    Returns:
        ``pos`` (n_slots, 3) m, ``quat`` (n_slots, 4) (w, x, y, z), ``size`` (n_slots, 3) half sizes m,
        ``aabb`` (n_slots, 6) local centre and half extents m, ``rbound`` (n_slots,) m.
    """
    n = _boxes_within(arena, n_slots)
    pos, quat, size = np.zeros((n_slots, 3)), np.zeros((n_slots, 4)), np.full((n_slots, 3), _PARK_SIZE)
    quat[:, 0] = 1.0
    pos[n:, 0] = (np.arange(n, n_slots) - n) * _PARK_PITCH
    pos[n:, 2] = PARK_Z
    for k, b in enumerate(arena.boxes):  # rounded as ArenaSpec.to_mjcf writes them
        pos[k] = [float(f"{v:.6g}") for v in (b.x, b.y, b.h / 2)]
        yaw = float(f"{b.yaw:.9g}")
        quat[k] = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
        size[k] = [float(f"{v:.6g}") for v in (b.sx / 2, b.sy / 2, b.h / 2)]
    aabb = np.concatenate([np.zeros((n_slots, 3)), size], axis=1)
    return {"pos": pos, "quat": quat, "size": size, "aabb": aabb, "rbound": np.linalg.norm(size, axis=1)}


def _boxes_within(arena: ArenaSpec, n_slots: int) -> int:
    """The arena's number of boxes; ValueError if it has more than ``n_slots``."""
    n = len(arena.boxes)
    if n > n_slots:
        raise ValueError(f"arena {arena.name!r} has {n} boxes, more than the {n_slots} obstacle slots")
    return n
