"""Many AMOSII worlds with their physics plugged in: AMOSII's sensing and sensor noise written once for all.

.. code-block:: text

    reset:  reset_physics() (each world at its arena's start pose); each world's noise from its Generator
    sense:  sensordata of all worlds -> noisy ultrasonic distances (n, 2), foot contacts (n, 6)   # as AmosII.observe
    apply, advance: the physics backend's (mujoco.batch threads, MuJoCo Warp)

:class:`AmosIIWorlds` implements the :class:`~neurowalk.body.world.World` protocol over n worlds; a subclass (an
engine's physics: :mod:`neurowalk.sim.batch`, :mod:`neurowalk.sim.warp_engine`) plugs in
:meth:`~AmosIIWorlds.reset_physics`, :meth:`~AmosIIWorlds.apply`, :meth:`~AmosIIWorlds.advance` and
:meth:`~AmosIIWorlds.warnings`, and fills :attr:`qpos`, :attr:`sensordata` and :attr:`sim_time` after each reset
and step. World i reads what :class:`~neurowalk.body.amosii.AmosII` in world i's arena would, bit for bit.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Sequence

import mujoco
import numpy as np

from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body.amosii_params import STAND_KEY, BodyParams
from neurowalk.body.amosii_sensors import joint_qpos_indices, sensed, sensor_layout
from neurowalk.body.noise import ColoredNoise, ColoredNoiseBatch
from neurowalk.body.world import ALL_COLUMNS
from neurowalk.observation import Observation

__all__ = ["AmosIIWorlds"]


class AmosIIWorlds(ABC):
    """n AMOSII worlds (a :class:`~neurowalk.body.world.World`); the physics is a subclass's.

    Args:
        arenas: each world's arena. noises: each world's sensor noise strength (0: none).
        model: the CPU ``MjModel`` of world 0 (sizes, names, sensor addresses; every world has its structure).
        params: the body's numbers. n_substeps: physics steps per control step.

    Attributes:
        qpos (n, nq), sensordata (n, nsensordata), sim_time (n,): the worlds' state after the last reset or step
            (the subclass fills them). xpos, xmat: (n, nbody, 3), (n, nbody, 9), bound by a subclass where a
            controller reads whole observations (:meth:`observation`), else None.
        noise: every world's sensor noise (2 ultrasonic, the joints and 6 feet channels, as AmosII's own source).
    """

    action = "targets"
    columns = ALL_COLUMNS

    def __init__(
        self,
        arenas: Sequence[ArenaSpec],
        noises: Sequence[float],
        model: mujoco.MjModel,
        params: BodyParams,
        n_substeps: int,
    ) -> None:
        self.arenas = list(arenas)
        self.n = len(self.arenas)
        self.model, self.params, self.n_substeps = model, params, n_substeps
        self.nq = model.nq
        self.layout = lay = sensor_layout(model)
        self.us_range = params.us_range
        self.joints = joint_qpos_indices(model)
        channels = 2 + len(self.joints) + 6  # as AmosII's own source
        self.noise = ColoredNoiseBatch([ColoredNoise(channels, strength=s) for s in noises])
        self.trunk = lay.trunk
        self.stand_key = model.key(STAND_KEY).id
        self.qpos: np.ndarray = np.zeros((self.n, model.nq))
        self.sensordata: np.ndarray = np.zeros((self.n, model.nsensordata))
        self.sim_time: np.ndarray = np.zeros(self.n)
        self.xpos: np.ndarray | None = None
        self.xmat: np.ndarray | None = None
        self._sensed: tuple[np.ndarray, np.ndarray] | None = None

    @property
    def qidx(self) -> np.ndarray:
        """The 19 joints' places in ``qpos[:, 7:]``."""
        return self.joints - 7

    @property
    def time(self) -> np.ndarray:
        """(n,) every world's simulated time (s)."""
        return self.sim_time

    @abstractmethod
    def reset_physics(self) -> None:
        """Every world standing at its arena's start pose (``place_at_start``), at rest, forward-computed."""

    @abstractmethod
    def apply(self, actions: np.ndarray) -> None:
        """Every world's joint targets (n, nu), rad."""

    @abstractmethod
    def advance(self) -> None:
        """One control step of physics in every world."""

    @abstractmethod
    def warnings(self, i: int) -> dict[str, int]:
        """World i's warnings so far, by name (empty when none)."""

    def reset(self, rngs: Sequence[np.random.Generator]) -> None:
        """Every world at its start pose, at rest; world i's noise from ``rngs[i]``."""
        self.reset_physics()
        self.noise.reset(list(rngs))

    def sense(self) -> tuple[np.ndarray, np.ndarray]:
        """Noisy ultrasonic distances (n, 2) in m (inf = no echo) and foot contacts (n, 6), as AmosII.observe.

        Advances every world's sensor noise by one control step (kept, with the readings, for :meth:`observation`).
        """
        noise = self.noise.step()
        dist, foot = sensed(self.layout, self.sensordata, self.us_range, noise)  # AmosII.observe's sensor model
        self._sensed = (dist, foot)
        return dist, foot

    def observation(self, i: int) -> Observation:
        """World i's full observation of this step (after :meth:`sense`; needs :attr:`xpos`, :attr:`xmat`)."""
        if self.xpos is None or self.xmat is None:
            raise ValueError(f"{type(self).__name__} reads no whole observations: its controllers step compiled")
        assert self._sensed is not None, "sense() first"
        nj = len(self.joints)
        dist, foot = self._sensed
        xpos, xmat = self.xpos[i, self.trunk], self.xmat[i, self.trunk]
        return Observation(
            us_distance=dist[i].copy(),
            foot_contact=foot[i].copy(),
            joint_angles=self.qpos[i, self.joints] + self.noise.value[i, 2 : 2 + nj],
            pose=np.array([xpos[0], xpos[1], math.atan2(xmat[3], xmat[0])]),
            time=float(self.sim_time[i]),
        )
