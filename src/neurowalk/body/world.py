"""The world protocol: a body as n worlds with a leading world axis, the one shape the loop steps.

.. code-block:: text

    worlds.reset(rngs)                  # each world at its arena's start pose, at rest; sensor noise from rngs[i]
    dist, foot = worlds.sense()         # (n, 2) ultrasonic distances (m, inf: no echo), (n, 6) foot contacts
    obs = worlds.observation(i)         # world i's whole reading of this step, for a controller stepped by act()
    worlds.apply(actions)               # (n, 19) joint targets (rad, actuator order) or (n, 2) steering pairs
    worlds.advance()                    # one control step of physics in every world
    worlds.qpos, worlds.time            # (n, nq) positions (qpos[:, 0:7]: the trunk's free joint), (n,) s

One world is the case n = 1: :class:`OneWorld` makes any per-step :class:`Body` (AMOSII, the wheeled robot, a user's
MJCF robot: ``reset(rng)``, ``observe()``, ``apply(action)``, ``advance()``, ``model``, ``data``) such a world.
Many AMOSII worlds with their physics plugged in are :class:`~neurowalk.body.amosii_worlds.AmosIIWorlds`. The loop
(:mod:`neurowalk.sim.loop`) steps every kind the same way.

Departure from DESIGN.md §4, which names the reading ``observe() -> Observation``: the loop's reading is split in
two, :meth:`World.sense` (what every loop reads and records, as arrays of all worlds) and
:meth:`World.observation` (one world's whole :class:`~neurowalk.observation.Observation`, built only for a
controller that needs it), so that compiled controllers of many worlds pay for no per-world objects.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol, TypeGuard, cast, runtime_checkable

import mujoco
import numpy as np

from neurowalk.observation import Observation

__all__ = ["ALL_COLUMNS", "Body", "CompiledWorld", "OneWorld", "World", "is_compiled"]

#: Every column of a run's rows (:class:`~neurowalk.sim.trajectory.Trajectory`): what a physics world fills.
ALL_COLUMNS: tuple[str, ...] = ("t", "pose", "inputs", "outputs", "b", "q", "targets", "joint_angles",
                                "us_distance", "foot_contact", "up_z", "qpos")  # fmt: skip

_STATE = mujoco.mjtState.mjSTATE_INTEGRATION


class Body(Protocol):
    """A per-step body of the registry, one world (AMOSII, the wheeled robot, a user's MJCF robot): what
    :class:`OneWorld` steps.

    Attributes:
        action: what :meth:`apply` takes, ``"targets"`` (19 joint targets, rad) or ``"steering"`` (O1, O2).
        n_substeps: physics steps per control step. model, data: its MuJoCo model and data.
    """

    action: str
    n_substeps: int
    model: mujoco.MjModel
    data: mujoco.MjData

    def reset(self, rng: np.random.Generator) -> None:
        """At its start pose, at rest; its sensor noise drawn from ``rng`` from now on."""

    def observe(self) -> Observation:
        """This control step's reading (advances the sensor noise by one step)."""
        ...

    def apply(self, action: np.ndarray) -> None:
        """Its action for the next control step."""

    def advance(self) -> None:
        """One control step of physics."""

    def warnings(self) -> dict[str, int]:
        """Its physics warnings so far, by name."""
        ...


class LeggedBody(Body, Protocol):
    """A per-step body with the 19 joints (``action == "targets"``)."""

    qidx: np.ndarray  # (19,) the joints' places in qpos


@runtime_checkable
class World(Protocol):
    """n worlds of one body, stepped together (see the module text).

    Attributes:
        n: the number of worlds. action: what :meth:`apply` takes, ``"targets"`` or ``"steering"``.
        nq: positions per world. qidx: the 19 joints' places in ``qpos[:, 7:]`` (None: a body without them).
        n_substeps: physics steps per control step.
    """

    n: int
    action: str
    nq: int
    n_substeps: int
    columns: tuple[str, ...]

    @property
    def qidx(self) -> np.ndarray | None: ...

    @property
    def qpos(self) -> np.ndarray:
        """(n, nq) positions now."""
        ...

    @property
    def time(self) -> np.ndarray:
        """(n,) simulated time now (s)."""
        ...

    def reset(self, rngs: Sequence[np.random.Generator]) -> None:
        """Every world at its start pose, at rest; world i's sensor noise drawn from ``rngs[i]`` from now on."""

    def sense(self) -> tuple[np.ndarray, np.ndarray]:
        """This step's noisy ultrasonic distances (n, 2) (m, inf: no echo) and foot contacts (n, 6); advances the
        sensor noise by one control step."""
        ...

    def observation(self, i: int) -> Observation:
        """World i's whole reading of this step (after :meth:`sense`)."""
        ...

    def apply(self, actions: np.ndarray) -> None:
        """Every world's action: (n, 19) joint targets (rad) or (n, 2) steering pairs."""

    def advance(self) -> None:
        """One control step of physics in every world."""

    def warnings(self, i: int) -> dict[str, int]:
        """World i's physics warnings so far, by name (empty when none)."""
        ...


class PlanarWorld(World, Protocol):
    """A world without positions (``nq`` 0, the planar surrogate stepped a step at a time): it gives its pose."""

    pose: np.ndarray  # (n, 3) x m, y m, yaw rad after the last step


@runtime_checkable
class CompiledWorld(Protocol):
    """One world whose body and controller step together in compiled chunks of control steps (the planar
    surrogate: its kinematics, sensing and the sensory network in one compiled call).

    Attributes:
        n: 1. action: ``"steering"``. nq: 0 (no positions beyond the pose). columns: the columns its rows fill.
    """

    n: int
    action: str
    nq: int
    n_substeps: int
    columns: tuple[str, ...]

    @property
    def qidx(self) -> None: ...

    def reset(self, rngs: Sequence[np.random.Generator]) -> None:
        """At the start pose, at rest; the sensor noise from ``rngs[0]``."""

    def rollout(
        self,
        k0: int,
        k1: int,
        cols: dict[str, np.ndarray],
        base: int,
        network: tuple[np.ndarray, np.ndarray] | None,
        steer: np.ndarray | None,
    ) -> None:
        """Control steps ``k0 .. k1 - 1``, row ``k - base`` of each of ``cols`` (1, rows, ...) after step k, steered
        by the sensory network's (state, packed params) arrays or a constant steering pair."""

    def warnings(self, i: int) -> dict[str, int]:
        """World i's warnings so far."""
        ...


def is_compiled(world: object) -> TypeGuard[CompiledWorld]:
    """Whether ``world`` steps in compiled chunks (:class:`CompiledWorld`: it has ``rollout``), asked as a run starts
    (an attribute lookup: a protocol's ``isinstance`` costs tens of µs, a planar run's whole budget is a few ms)."""
    return hasattr(world, "rollout")


class OneWorld:
    """A per-step body as a :class:`World` of one world (n = 1).

    Args:
        body: a body of the registry with ``reset(rng)``, ``observe()``, ``apply(action)``, ``advance()``,
            ``warnings()``, ``model`` and ``data`` (AMOSII, the wheeled robot, a user's MJCF robot).
    """

    n = 1
    columns = ALL_COLUMNS

    def __init__(self, body: Body) -> None:
        self.body = body
        self.action: str = body.action
        self.nq: int = body.model.nq
        self.n_substeps: int = body.n_substeps
        self._data = body.data
        self._obs: Observation | None = None
        legged = body.action == "targets"
        self._qidx: np.ndarray | None = cast("LeggedBody", body).qidx - 7 if legged else None

    @property
    def qidx(self) -> np.ndarray | None:
        """The 19 joints' places in ``qpos[7:]`` (a legged body), else None."""
        return self._qidx

    @property
    def qpos(self) -> np.ndarray:
        """(1, nq) the body's positions (a view)."""
        return self._data.qpos[None]

    @property
    def time(self) -> np.ndarray:
        """(1,) the body's simulated time (s)."""
        return np.array([self._data.time])

    def reset(self, rngs: Sequence[np.random.Generator]) -> None:
        """The body at its arena's start pose, its sensor noise from ``rngs[0]``."""
        self.body.reset(rngs[0])

    def sense(self) -> tuple[np.ndarray, np.ndarray]:
        """The body's observation of this step (kept for :meth:`observation`); its distances and contacts (1, k)."""
        obs = self._obs = self.body.observe()
        return obs.us_distance[None], obs.foot_contact[None]

    def observation(self, i: int) -> Observation:
        """The observation :meth:`sense` took."""
        assert self._obs is not None, "sense() first"
        return self._obs

    def apply(self, actions: np.ndarray) -> None:
        """The body's action: row 0 of ``actions``."""
        self.body.apply(actions[0])

    def advance(self) -> None:
        """One control step of the body's physics."""
        self.body.advance()

    def advance_keeping_previous(self) -> np.ndarray:
        """:meth:`advance`, returning the integration state before its last physics step (what a checkpoint needs
        to go on bit for bit)."""
        m, d, n = self.body.model, self._data, self.n_substeps
        if n > 1:
            mujoco.mj_step(m, d, nstep=n - 1)
        prev = np.empty(mujoco.mj_stateSize(m, _STATE))
        mujoco.mj_getState(m, d, prev, _STATE)
        mujoco.mj_step(m, d)
        return prev

    def warnings(self, i: int) -> dict[str, int]:
        """The body's warnings so far."""
        return self.body.warnings()
