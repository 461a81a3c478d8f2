"""Obstacle slots: a fixed number of box geoms in AMOSII's world, given an arena's boxes after compilation.

One compiled model with ``n`` slots then serves every arena of at most ``n`` boxes: the single control loop
writes one arena into its model (``AmosII(arena, pad_boxes=n)``, :func:`put_arena`), and
:mod:`neurowalk.sim.batch` writes one arena per simulation of a ``mujoco.batch.Batch`` through its
per-simulation model fields. Both go through :func:`write_slots` and then MuJoCo's ``mj_setConst``, which
recomputes the world body's bounding-volume boxes around the moved geoms, so the two models are the same
number for number.

A slot holding box ``k`` of an arena takes every per-geom value (pose, size, bounding sphere and box,
friction, colour, ...) from the arena's own model compiled as usual, so that box behaves exactly as in the
unpadded model. A slot the arena does not use stays parked as compiled: a small invisible box 10 m below the
floor. World geoms never collide with each other, the robot stays above the floor, and a ray from the robot
meets the floor plane long before it could reach a parked box, so a parked slot can touch nothing.

Slots keep MuJoCo's default contype/conaffinity of 1, so that the compiler puts them into the world body's
bounding-volume hierarchy (a geom that cannot collide is left out of it, and moving it later would leave it
out of the midphase). The hierarchy only prunes candidate pairs, and MuJoCo sorts the contacts it finds by
geom id, so the contacts do not depend on the tree's shape: measured, a padded model gives the same
trajectory, bit for bit, as the plain one (tests/sim/test_batch.py).
"""

from __future__ import annotations

import weakref
from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np

from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body.amosii import amosii_xml
from neurowalk.body.amosii_params import BodyParams

__all__ = ["GEOM_FIELDS", "SLOT_PREFIX", "SlotLayout", "arena_slot_values", "model_slot_values", "put_arena",
           "slot_layout", "slots_mjcf", "write_slots"]  # fmt: skip

SLOT_PREFIX = "obstacle_slot_"
"""Geom names of the slots: ``obstacle_slot_0`` ... in slot order."""
PARK_Z = -10.0
"""Height (m) of a parked slot's centre, far below the floor."""

GEOM_FIELDS: tuple[str, ...] = (
    "geom_pos", "geom_quat", "geom_size", "geom_rbound", "geom_aabb", "geom_sameframe", "geom_rgba",
    "geom_friction", "geom_solref", "geom_solimp", "geom_solmix", "geom_margin", "geom_gap", "geom_condim",
    "geom_priority", "geom_contype", "geom_conaffinity", "geom_group",
)  # fmt: skip
"""Per-geom model fields a slot takes from the arena's box (everything but type, body and ids)."""


def slots_mjcf(n_slots: int) -> str:
    """MJCF of ``n_slots`` parked box geoms, for the world body (``amosii_xml(world=...)``)."""
    if n_slots < 0:
        raise ValueError(f"the number of obstacle slots must be >= 0, got {n_slots}")
    return "\n".join(
        f'    <geom name="{SLOT_PREFIX}{k}" type="box" size="0.05 0.05 0.05" pos="0 0 {PARK_Z:g}" '
        f'rgba="0.55 0.45 0.35 0"/>'
        for k in range(n_slots)
    )


@dataclass(frozen=True, eq=False)
class SlotLayout:
    """Where the slots sit in a compiled padded model, and their parked values.

    Attributes:
        geoms: (n_slots,) geom ids of the slots, in slot order.
        parked: the slots' compiled (parked) values, field -> (n_slots, ...) array.
    """

    geoms: np.ndarray
    parked: dict[str, np.ndarray]

    @property
    def n_slots(self) -> int:
        """Number of slots."""
        return len(self.geoms)


_LAYOUTS: weakref.WeakKeyDictionary[mujoco.MjModel, SlotLayout] = weakref.WeakKeyDictionary()


def slot_layout(model: mujoco.MjModel) -> SlotLayout:
    """The slot layout of a padded model, read (once) while its slots still hold the compiled values."""
    layout = _LAYOUTS.get(model)
    if layout is None:
        n = 0
        while mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"{SLOT_PREFIX}{n}") >= 0:
            n += 1
        geoms = np.array([model.geom(f"{SLOT_PREFIX}{k}").id for k in range(n)], dtype=int)
        if np.any(model.geom_bodyid[geoms] != 0):
            raise ValueError("obstacle slots must be geoms of the world body")
        parked = {f: getattr(model, f)[geoms].copy() for f in GEOM_FIELDS}
        layout = _LAYOUTS[model] = SlotLayout(geoms=geoms, parked=parked)
    return layout


def model_slot_values(model: mujoco.MjModel) -> dict[str, np.ndarray]:
    """Per-geom values of the boxes ``obstacle_0, obstacle_1, ...`` of a compiled plain (unpadded) model.

    Returns:
        field -> (n_boxes, ...) array, for every field of :data:`GEOM_FIELDS`.
    """
    ids = []
    while (g := mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"obstacle_{len(ids)}")) >= 0:
        ids.append(g)
    idx = np.array(ids, dtype=int)
    return {f: getattr(model, f)[idx].copy() for f in GEOM_FIELDS}


def arena_slot_values(arena: ArenaSpec, params: BodyParams | None = None) -> dict[str, np.ndarray]:
    """Per-geom values of the arena's boxes as MuJoCo compiles them into the plain model (compiles it, ~2 ms)."""
    model = mujoco.MjModel.from_xml_string(amosii_xml(params or BodyParams(), world=arena.to_mjcf()))
    values = model_slot_values(model)
    if len(values["geom_pos"]) != len(arena.boxes):
        raise ValueError(f"arena {arena.name!r}: found {len(values['geom_pos'])} of its {len(arena.boxes)} boxes")
    return values


def write_slots(fields: Mapping[str, np.ndarray], layout: SlotLayout, values: Mapping[str, np.ndarray]) -> None:
    """Put an arena's boxes into the slots of one model (in place); run ``mj_setConst`` afterwards.

    Args:
        fields: model field -> that model's whole array (``model.geom_pos``, or one simulation's row of a
            batch's ``expand("geom_pos")``), for every name in :data:`GEOM_FIELDS`.
        layout: the model's :func:`slot_layout`.
        values: from :func:`model_slot_values`; its k-th row goes into slot k, the other slots stay parked.

    Raises:
        ValueError: if the arena has more boxes than the model has slots.
    """
    n = len(values["geom_pos"])
    if n > layout.n_slots:
        raise ValueError(f"the arena has {n} boxes but the model only {layout.n_slots} obstacle slots")
    for f in GEOM_FIELDS:
        fields[f][layout.geoms] = np.concatenate([values[f], layout.parked[f][n:]]) if n else layout.parked[f]


def put_arena(model: mujoco.MjModel, values: Mapping[str, np.ndarray]) -> None:
    """Put an arena's boxes into a padded model's slots and update the constants derived from them."""
    layout = slot_layout(model)
    write_slots({f: getattr(model, f) for f in GEOM_FIELDS}, layout, values)
    mujoco.mj_setConst(model, mujoco.MjData(model))
