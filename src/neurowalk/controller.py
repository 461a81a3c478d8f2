"""Controllers: from an :class:`~neurowalk.observation.Observation` to 19 joint targets.

Every controller follows the small :class:`Controller` protocol (``reset(rng)``, ``act(obs)``) and
exposes the steering pair (O1, O2) it used last, so that a body that only needs steering (the
planar surrogate) can read it and the recorder can log it.

* :class:`NeuralController`: the paper's closed loop: ultrasonic distances → inputs (I1, I2) →
  sensory network (plastic, static or Braitenberg) → steering (O1, O2) → locomotion network.
* :class:`FixedController`: constant steering through the same locomotion network.

Climbing (optional, both controllers): :class:`~neurowalk.neural.leg_control.LegControl` shapes the
locomotion network's pre-motor signals from the foot contacts (forward models, searching and
elevation reflexes), and :class:`~neurowalk.neural.backbone.BackboneControl` drives the backbone joint
from the obstacle-height sensor and masks the ultrasonic inputs while a climbable step is ahead.
Without them the backbone target stays 0.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from neurowalk import anatomy
from neurowalk.neural.backbone import BackboneControl, BackboneParams
from neurowalk.neural.leg_control import LegControl, LegControlParams
from neurowalk.neural.motor import LocomotionNetwork, LocomotionParams, motor_map
from neurowalk.neural.sensory import Mode, SensoryNetwork, SensoryParams
from neurowalk.observation import Observation

CONTROLLERS: tuple[str, ...] = ("plastic", "static", "braitenberg", "fixed")


@runtime_checkable
class Controller(Protocol):
    """What the control loop needs of a controller."""

    steering: np.ndarray  # (2,) last steering (O1, O2)
    inputs: np.ndarray  # (2,) last sensory inputs (I1, I2)

    def reset(self, rng: np.random.Generator | None = None) -> None:
        """Start a new episode."""
        ...

    def act(self, observation: Observation) -> np.ndarray:
        """Return (19,) joint targets in rad, actuator order (anatomy.ACTUATORS)."""
        ...


class _Climbing:
    """Leg reflexes and backbone control around a locomotion network (either may be off)."""

    def __init__(self, reflexes: LegControlParams | bool | None, backbone: BackboneParams | bool | None) -> None:
        self.legs = LegControl(reflexes if isinstance(reflexes, LegControlParams) else None) if reflexes else None
        self.backbone = (
            BackboneControl(backbone if isinstance(backbone, BackboneParams) else None) if backbone else None
        )

    @property
    def on(self) -> bool:
        return self.legs is not None or self.backbone is not None

    def reset(self) -> None:
        for part in (self.legs, self.backbone):
            if part is not None:
                part.reset()

    def masks_us(self, obs: Observation) -> bool:
        """Update the backbone from the terrain; whether the ultrasonic inputs are masked this step."""
        if self.backbone is None:
            return False
        self.backbone.step(obs.obstacle_height, obs.ground_height)
        return self.backbone.climbing

    def targets(self, loc: LocomotionNetwork, o1: float, o2: float, obs: Observation, out: np.ndarray) -> np.ndarray:
        pre = loc.step_presignals(o1, o2)
        if self.legs is not None:
            self.legs.step(pre, obs.foot_contact, self.legs.uneven(obs.obstacle_height, obs.ground_height))
        motor_map(pre[0], pre[1], pre[2], out)
        out[anatomy.N_ACTUATORS - 1] = self.backbone.command if self.backbone is not None else 0.0
        return out


class NeuralController:
    """Sensory network + locomotion network: the paper's adaptive neural closed-loop controller.

    Args:
        mode: sensory network mode, ``plastic``, ``static`` or ``braitenberg``.
        sensory: sensory network parameters.
        locomotion: locomotion network parameters (gait, delays).
        b0: start self-connection weight b of the plastic network (see :func:`simulate`).
        q0: start learned inhibition q of the plastic network.
        reflexes: local leg control (True for the defaults, or its parameters); off by default.
        backbone: backbone joint control for climbing (True or its parameters); off by default. It
            needs a body that reads the obstacle-height sensor.
    """

    def __init__(
        self,
        mode: Mode = "plastic",
        *,
        sensory: SensoryParams | None = None,
        locomotion: LocomotionParams | None = None,
        b0: object = None,
        q0: object = None,
        reflexes: LegControlParams | bool | None = None,
        backbone: BackboneParams | bool | None = None,
    ) -> None:
        self.mode = mode
        self.sensory = SensoryNetwork(mode, params=sensory, b0=b0, q0=q0)
        self.locomotion = LocomotionNetwork(locomotion)
        self.climbing = _Climbing(reflexes, backbone)
        self.inputs = np.zeros(2)
        self.steering = np.zeros(2)
        self._targets = np.zeros(anatomy.N_ACTUATORS)

    def reset(self, rng: np.random.Generator | None = None) -> None:
        """Back to the start weights and network state (the controller draws no random numbers)."""
        self.sensory.reset()
        self.locomotion.reset()
        self.climbing.reset()
        self.inputs[:] = 0.0
        self.steering[:] = 0.0

    def act(self, observation: Observation) -> np.ndarray:
        """One control step: (19,) joint targets in rad, actuator order (a fresh array)."""
        d = observation.us_distance
        i1, i2 = self.sensory.input(float(d[0])), self.sensory.input(float(d[1]))
        if self.climbing.masks_us(observation):
            i1 = i2 = -1.0  # a climbable step ahead: not an obstacle to avoid
        o1, o2 = self.sensory.step(i1, i2)
        self.inputs[0], self.inputs[1] = i1, i2
        self.steering[0], self.steering[1] = o1, o2
        if self.climbing.on:
            return self.climbing.targets(self.locomotion, o1, o2, observation, np.zeros(anatomy.N_ACTUATORS))
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

    def __init__(
        self,
        steer: tuple[float, float],
        *,
        locomotion: LocomotionParams | None = None,
        reflexes: LegControlParams | bool | None = None,
        backbone: BackboneParams | bool | None = None,
    ) -> None:
        s = np.asarray(steer, dtype=float)
        if s.shape != (2,) or not np.all(np.isfinite(s)) or np.any(np.abs(s) > 1.0):
            raise ValueError(f"steer must be two numbers in [-1, 1], got {steer!r}")
        self.steering = s
        self.mode = "fixed"
        self.inputs = np.full(2, -1.0)
        self.locomotion = LocomotionNetwork(locomotion)
        self.climbing = _Climbing(reflexes, backbone)

    def reset(self, rng: np.random.Generator | None = None) -> None:
        """Back to the start of the locomotion network."""
        self.locomotion.reset()
        self.climbing.reset()

    def act(self, observation: Observation) -> np.ndarray:
        """(19,) joint targets in rad for the fixed steering."""
        o1, o2 = self.steering
        if self.climbing.on:
            self.climbing.masks_us(observation)
            return self.climbing.targets(self.locomotion, o1, o2, observation, np.zeros(anatomy.N_ACTUATORS))
        return self.locomotion.step(o1, o2).copy()


def make_controller(name: str, *, steer: tuple[float, float] | None = None, **kwargs: object) -> Controller:
    """Build a controller by name: ``plastic``, ``static``, ``braitenberg`` or ``fixed``."""
    if name == "fixed":
        if steer is None:
            raise ValueError("controller 'fixed' needs a steering pair (O1, O2)")
        return FixedController(steer, **kwargs)  # type: ignore[arg-type]
    if name not in CONTROLLERS:
        raise ValueError(f"unknown controller {name!r}; expected one of {CONTROLLERS}")
    return NeuralController(name, **kwargs)  # type: ignore[arg-type]
