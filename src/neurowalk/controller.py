"""Controllers: from an :class:`~neurowalk.observation.Observation` to 19 joint targets.

Every controller follows the small :class:`Controller` protocol (``reset(rng)``, ``act(obs)``) and
exposes the steering pair (O1, O2) it used last, so that a body that only needs steering (the
planar surrogate) can read it and the recorder can log it.

* :class:`NeuralController`: the paper's closed loop: ultrasonic distances → inputs (I1, I2) →
  sensory network (plastic, static or Braitenberg) → steering (O1, O2) → locomotion network.
* :class:`FixedController`: constant steering through the same locomotion network.

The backbone target stays 0 until climbing is built.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from neurowalk import anatomy
from neurowalk.neural.motor import LocomotionNetwork, LocomotionParams
from neurowalk.neural.sensory import Mode, SensoryNetwork, SensoryParams, distance_input
from neurowalk.observation import Observation

CONTROLLERS: tuple[str, ...] = ("plastic", "static", "braitenberg", "fixed")


@runtime_checkable
class Controller(Protocol):
    """What the control loop needs of a controller."""

    steering: np.ndarray  # (2,) last steering (O1, O2)

    def reset(self, rng: np.random.Generator) -> None:
        """Start a new episode."""
        ...

    def act(self, observation: Observation) -> np.ndarray:
        """Return (19,) joint targets in rad, actuator order (anatomy.ACTUATORS)."""
        ...


class NeuralController:
    """Sensory network + locomotion network: the paper's adaptive neural closed-loop controller.

    Args:
        mode: sensory network mode, ``plastic``, ``static`` or ``braitenberg``.
        sensory: sensory network parameters.
        locomotion: locomotion network parameters (gait, delays).
        b0, q0: start weights of the plastic network (see :func:`simulate`).
    """

    def __init__(
        self,
        mode: Mode = "plastic",
        *,
        sensory: SensoryParams | None = None,
        locomotion: LocomotionParams | None = None,
        b0: object = None,
        q0: object = None,
    ) -> None:
        self.mode = mode
        self.sensory = SensoryNetwork(mode, params=sensory, b0=b0, q0=q0)
        self.locomotion = LocomotionNetwork(locomotion)
        self.inputs = np.zeros(2)
        self.steering = np.zeros(2)
        self._targets = np.zeros(anatomy.N_ACTUATORS)

    def reset(self, rng: np.random.Generator | None = None) -> None:
        """Back to the start weights and network state (the controller draws no random numbers)."""
        self.sensory.reset()
        self.locomotion.reset()
        self.inputs[:] = 0.0
        self.steering[:] = 0.0

    def act(self, observation: Observation) -> np.ndarray:
        """One control step: (19,) joint targets in rad, actuator order (a fresh array)."""
        d = observation.us_distance
        i1, i2 = distance_input(float(d[0])), distance_input(float(d[1]))
        o1, o2 = self.sensory.step(i1, i2)
        self.inputs[0], self.inputs[1] = i1, i2
        self.steering[0], self.steering[1] = o1, o2
        return self.locomotion.step(o1, o2).copy()

    @property
    def b(self) -> np.ndarray:
        """(2,) self weights of the sensory network."""
        return self.sensory.b

    @property
    def q(self) -> np.ndarray:
        """(2,) inhibition magnitudes of the sensory network (c = -(q1 + q2)/2)."""
        return self.sensory.q


class FixedController:
    """Constant steering (O1, O2) through the locomotion network; ignores the sensors."""

    def __init__(self, steer: tuple[float, float], *, locomotion: LocomotionParams | None = None) -> None:
        s = np.asarray(steer, dtype=float)
        if s.shape != (2,) or not np.all(np.isfinite(s)) or np.any(np.abs(s) > 1.0):
            raise ValueError(f"steer must be two numbers in [-1, 1], got {steer!r}")
        self.steering = s
        self.mode = "fixed"
        self.inputs = np.full(2, -1.0)
        self.locomotion = LocomotionNetwork(locomotion)

    def reset(self, rng: np.random.Generator | None = None) -> None:
        """Back to the start of the locomotion network."""
        self.locomotion.reset()

    def act(self, observation: Observation) -> np.ndarray:
        """(19,) joint targets in rad for the fixed steering."""
        return self.locomotion.step(self.steering[0], self.steering[1]).copy()


def make_controller(name: str, *, steer: tuple[float, float] | None = None, **kwargs: object) -> Controller:
    """Build a controller by name: ``plastic``, ``static``, ``braitenberg`` or ``fixed``."""
    if name == "fixed":
        if steer is None:
            raise ValueError("controller 'fixed' needs a steering pair (O1, O2)")
        return FixedController(steer, **kwargs)  # type: ignore[arg-type]
    if name not in CONTROLLERS:
        raise ValueError(f"unknown controller {name!r}; expected one of {CONTROLLERS}")
    return NeuralController(name, **kwargs)  # type: ignore[arg-type]
