"""``check_body``: the body contract tested, as Gymnasium's ``check_env`` tests an environment's.

.. code-block:: python

    from neurowalk import make_arena, make_body
    from neurowalk.body.check import check_body

    check_body(make_body("mjcf:my_robot.xml", make_arena("corner")))   # BodyContractError: one line naming what

A per-step body (``reset(rng)``, ``observe()``, ``apply(action)``, ``advance()``, ``model``, ``data``) is checked as
the one world the loop makes of it (:class:`~neurowalk.body.world.OneWorld`); a :class:`~neurowalk.body.world.World`
of many worlds and a :class:`~neurowalk.body.world.CompiledWorld` as they are. What is checked: the attributes the
loop reads; the shapes and units of a reading (distances > 0 m or ``inf``, contacts in [0, 1]); positions and time
finite, time going forward by a control step; a world at its arena's start pose after a reset; the same seeds
giving the same readings and positions, bit for bit.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from neurowalk.body.world import ALL_COLUMNS, Body, CompiledWorld, OneWorld, World, is_compiled
from neurowalk.observation import Observation

__all__ = ["BodyContractError", "check_body"]


class BodyContractError(ValueError):
    """A body breaks the contract the loop relies on; the message is one line naming what."""


def check_body(body: object, *, steps: int = 5, seed: int = 0) -> None:
    """Test ``body`` against the body contract over ``steps`` control steps from ``seed``; raise
    :class:`BodyContractError` (one line naming the body and what is wrong) where it breaks it."""
    name = str(getattr(body, "name", type(body).__name__))
    try:
        if is_compiled(body):
            _check_compiled(body, steps, seed)
            if not isinstance(body, World):
                return
        world = body if isinstance(body, World) else OneWorld(_per_step(body))
        _check_attributes(world)
        first = _run(world, steps, seed)
        again = _run(world, steps, seed)
        for (k, a), b in zip(enumerate(first), again, strict=True):
            for label, x, y in zip(("distances", "contacts", "positions"), a, b, strict=True):
                if not np.array_equal(x, y, equal_nan=True):
                    raise BodyContractError(f"the same seed gave other {label} at step {k}: not deterministic")
    except BodyContractError as e:
        raise BodyContractError(f"body {name!r}: {e}") from None


def _per_step(body: object) -> Body:
    missing = [m for m in ("reset", "observe", "apply", "advance", "warnings", "model", "data", "action", "n_substeps")
               if not hasattr(body, m)]  # fmt: skip
    if missing:
        raise BodyContractError(f"a per-step body needs {', '.join(missing)}")
    return cast("Body", body)


def _check_attributes(world: World | CompiledWorld) -> None:
    n = getattr(world, "n", None)
    if not isinstance(n, int) or n < 1:
        raise BodyContractError(f"n must be a whole number of worlds >= 1, got {n!r}")
    if world.action not in ("targets", "steering"):
        raise BodyContractError(f"action must be 'targets' or 'steering', got {world.action!r}")
    if not isinstance(world.n_substeps, int) or world.n_substeps < 1:
        raise BodyContractError(f"n_substeps must be a whole number >= 1, got {world.n_substeps!r}")
    unknown = sorted(set(world.columns) - set(ALL_COLUMNS))
    if unknown:
        raise BodyContractError(f"columns {unknown} are not a trajectory's ({', '.join(ALL_COLUMNS)})")


def _run(world: World, steps: int, seed: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Reset from ``seed`` and step with a still action; every step's readings and positions, checked."""
    n = world.n
    rngs = [np.random.default_rng(np.random.SeedSequence([seed, i])) for i in range(n)]
    world.reset(rngs)
    _check_start(world)
    action = np.zeros((n, 19 if world.action == "targets" else 2))
    if world.action == "steering":
        action[:] = -1.0  # straight ahead
    rows = []
    for k in range(steps):
        dist, foot = world.sense()
        _check_reading(dist, foot, n, k)
        obs = world.observation(0)
        if not isinstance(obs, Observation):
            raise BodyContractError(f"observation(0) must be an Observation, got {type(obs).__name__}")
        if not np.array_equal(obs.us_distance, dist[0]):
            raise BodyContractError(f"observation(0).us_distance {obs.us_distance} is not sense()'s {dist[0]}")
        t0 = np.array(world.time, dtype=float)
        world.apply(action)
        world.advance()
        qpos, t = np.array(world.qpos, dtype=float), np.array(world.time, dtype=float)
        if qpos.shape != (n, world.nq) or not np.isfinite(qpos).all():
            raise BodyContractError(f"qpos must be {n} x {world.nq} finite numbers after a step, got {qpos.shape}")
        if t.shape != (n,) or not (t > t0).all():
            raise BodyContractError(f"time must go forward in every world with a control step (step {k})")
        rows.append((dist, foot, qpos))
    return rows


def _check_start(world: World) -> None:
    qpos = np.asarray(world.qpos)
    if qpos.shape != (world.n, world.nq):
        raise BodyContractError(f"qpos must have shape ({world.n}, {world.nq}), got {qpos.shape}")
    arenas = getattr(world, "arenas", None) or [getattr(getattr(world, "body", None), "arena", None)]
    for i, arena in enumerate(arenas):
        if arena is not None and world.nq >= 7 and not np.allclose(qpos[i, 0:2], arena.start[:2]):
            raise BodyContractError(f"world {i} starts at {qpos[i, 0:2]}, not at its arena's start {arena.start[:2]}")


def _check_reading(dist: np.ndarray, foot: np.ndarray, n: int, k: int) -> None:
    dist, foot = np.asarray(dist), np.asarray(foot)
    if dist.shape != (n, 2):
        raise BodyContractError(f"sense() must give distances of shape ({n}, 2), got {dist.shape}")
    if foot.shape != (n, 6):
        raise BodyContractError(f"sense() must give foot contacts of shape ({n}, 6), got {foot.shape}")
    if np.isnan(dist).any():
        raise BodyContractError(f"distances must be numbers of m or inf (no echo), got {dist.tolist()} at step {k}")
    if not ((foot >= 0) & (foot <= 1)).all():
        raise BodyContractError(f"foot contacts must be in [0, 1], got {foot.tolist()} at step {k}")


def _check_compiled(world: CompiledWorld, steps: int, seed: int) -> None:
    """A compiled world: its chunks of steps with a constant steering, twice from one seed."""
    if world.n != 1 or world.action != "steering" or world.nq != 0:
        raise BodyContractError("a compiled world is one world (n = 1) taking the steering pair, without qpos")
    _check_attributes(world)
    runs = []
    for _ in range(2):
        cols = {k: np.full((1, steps, d), np.nan) for k, d in
                (("pose", 3), ("inputs", 2), ("outputs", 2), ("b", 2), ("q", 2), ("us_distance", 2))}  # fmt: skip
        world.reset([np.random.default_rng(seed)])
        world.rollout(0, steps, cols, 0, None, np.array([-1.0, -1.0]))
        for label in ("pose", "us_distance"):
            if np.isnan(cols[label]).any():
                raise BodyContractError(f"rollout() left rows of {label} unwritten")
        runs.append(cols)
    if not all(np.array_equal(runs[0][k], runs[1][k], equal_nan=True) for k in runs[0]):
        raise BodyContractError("the same seed gave another run: not deterministic")
