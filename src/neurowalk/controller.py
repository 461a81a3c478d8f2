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

import functools
from collections.abc import Callable, Mapping
from typing import Protocol, runtime_checkable

import numpy as np

from neurowalk import anatomy
from neurowalk.fileio import load_ref, user_ref
from neurowalk.neural.backbone import BackboneControl, BackboneParams
from neurowalk.neural.leg_control import LegControl, LegControlParams
from neurowalk.neural.motor import LocomotionNetwork, LocomotionParams, motor_map
from neurowalk.neural.sensory import Mode, SensoryNetwork, SensoryParams
from neurowalk.observation import Observation


@runtime_checkable
class Controller(Protocol):
    """What the control loop needs of a controller.

    A controller may declare state to record: ``recorded``, a mapping of its attributes' names to the shape of one
    row (``()`` a number, ``(3,)`` three), read after each ``act`` and kept in ``trajectory.npz`` as
    ``state.NAME`` (e.g. ``recorded = {"alarm": (2,)}``). The sensory network's weights b and q are the
    trajectory's own columns.
    """

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
        rule: the sensory network's step (a user's learning rule, :mod:`neurowalk.neural.variants`); None: the
            paper's, compiled.
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
        rule: Callable[[np.ndarray, float, float, np.ndarray], None] | None = None,
    ) -> None:
        self.mode = mode
        self.sensory = SensoryNetwork(mode, params=sensory, b0=b0, q0=q0, rule=rule)
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


def _fixed(*, steer: tuple[float, float] | None = None, **kwargs: object) -> Controller:
    if steer is None:
        raise ValueError("controller 'fixed' needs a steering pair (O1, O2)")
    return FixedController(steer, **kwargs)  # type: ignore[arg-type]


#: The built-in controllers: name -> the function that builds one from its settings (``steer``, ``sensory``,
#: ``locomotion``, ``b0``, ``q0``, ``reflexes``, ``backbone``). A user's controller is a file: ``FILE.py:NAME``.
BUILT_IN: dict[str, Callable[..., Controller]] = {
    "plastic": functools.partial(NeuralController, "plastic"),
    "static": functools.partial(NeuralController, "static"),
    "braitenberg": functools.partial(NeuralController, "braitenberg"),
    "fixed": _fixed,
}
CONTROLLERS: tuple[str, ...] = tuple(BUILT_IN)


def make_controller(name: str, *, steer: tuple[float, float] | None = None, **kwargs: object) -> Controller:
    """Build a controller by name: one of :data:`CONTROLLERS` with its settings, or a user's ``FILE.py:NAME``
    (:func:`load_controller`: NAME called with no arguments)."""
    if is_user_controller(name):
        return load_controller(name)()
    if name not in BUILT_IN:
        raise ValueError(f"unknown controller {name!r}; expected one of {', '.join(CONTROLLERS)}, or FILE.py:NAME")
    if name != "fixed" and steer is not None:
        raise ValueError(f"controller {name!r} takes no steering pair")
    return BUILT_IN[name](**({"steer": steer} if name == "fixed" else {}), **kwargs)


class ControllerFileError(ValueError):
    """What is wrong with a user's controller reference ``FILE.py:NAME`` or its file, in one line."""


def is_user_controller(name: str) -> bool:
    """Whether ``name`` names a user's controller, ``FILE.py:NAME`` (a built-in's name has no ``.py:``)."""
    return user_ref(name) is not None


def load_controller(name: str) -> Callable[[], Controller]:
    """What builds the user's controller ``FILE.py:NAME``: the file's ``NAME`` (a class or a function called with no
    arguments for each run). The file runs as a module once per process (again where its bytes change);
    :class:`ControllerFileError` in one line naming the file where it cannot be read or fails, or has no such
    callable."""
    _, factory = load_ref(name, "neurowalk_controller_", ControllerFileError)
    if not callable(factory):
        raise ControllerFileError(f"{name!r} is a {type(factory).__name__}, not a class or function")
    return factory  # type: ignore[no-any-return]


def recorded_state(controller: object) -> dict[str, tuple[int, ...]]:
    """A controller's declared state (``recorded``: name -> one row's shape), checked: names of attributes,
    shapes of whole numbers >= 1 (a number: the shape ``(n,)``); ValueError names what is wrong."""
    declared = getattr(controller, "recorded", None) or {}
    what = type(controller).__name__
    if not isinstance(declared, Mapping):
        raise ValueError(f"controller {what}: recorded must map names to row shapes, got {declared!r}")
    out = {}
    for key, shape in declared.items():
        if not isinstance(key, str) or not key.isidentifier():
            raise ValueError(f"controller {what}: recorded name {key!r} is not an attribute's name")
        dims = (shape,) if isinstance(shape, int) else tuple(shape)
        if not all(isinstance(d, int) and not isinstance(d, bool) and d >= 1 for d in dims):
            raise ValueError(f"controller {what}: recorded {key!r} has shape {shape!r}, not whole numbers >= 1")
        out[key] = dims
    return out


class ControllerContractError(ValueError):
    """A controller breaks the contract the loop relies on; the message is one line naming what."""


def check_controller(controller: Controller | str, *, steps: int = 20, seed: int = 0) -> None:
    """Test a controller (or a name: a built-in's, a user's ``FILE.py:NAME``) against the contract the loop relies
    on, as :func:`~neurowalk.body.check.check_body` tests a body: ``reset(rng)``, ``act(observation)`` giving (19,)
    finite joint targets in rad, ``steering`` two numbers in [-1, 1], its declared state (``recorded``) there in
    its shapes, and the same Generator giving the same steps bit for bit, over ``steps`` steps of readings that
    sweep an obstacle from out of range (no echo) to 0.1 m on either side. :class:`ControllerContractError` in
    one line naming the controller and what is wrong."""
    ctrl = make_controller(controller) if isinstance(controller, str) else controller
    name = controller if isinstance(controller, str) else type(controller).__name__
    try:
        missing = [a for a in ("reset", "act", "steering") if not hasattr(ctrl, a)]
        if missing:
            raise ControllerContractError(f"it needs {', '.join(missing)}")
        try:
            recorded = recorded_state(ctrl)
        except ValueError as e:
            raise ControllerContractError(str(e).partition(": ")[2]) from None
        far = np.linspace(2.0, 0.1, steps)
        readings = [np.array([d, np.inf]) if k % 2 == 0 else np.array([np.inf, d]) for k, d in enumerate(far)]
        runs = [_steps(ctrl, readings, recorded, seed) for _ in range(2)]
        for k, (a, b) in enumerate(zip(*runs, strict=True)):
            if not all(np.array_equal(x, y, equal_nan=True) for x, y in zip(a, b, strict=True)):
                raise ControllerContractError(f"the same Generator gave another step {k}: not deterministic")
    except ControllerContractError as e:
        raise ControllerContractError(f"controller {name!r}: {e}") from None


def _steps(
    ctrl: Controller, readings: list[np.ndarray], recorded: dict[str, tuple[int, ...]], seed: int
) -> list[list[np.ndarray]]:
    """Each step's targets, steering and declared state, each checked, from a reset with ``seed``."""
    ctrl.reset(np.random.default_rng(seed))
    rows = []
    for k, dist in enumerate(readings):
        targets = np.asarray(ctrl.act(Observation(us_distance=dist)), dtype=float)
        if targets.shape != (anatomy.N_ACTUATORS,) or not np.isfinite(targets).all():
            n = anatomy.N_ACTUATORS
            raise ControllerContractError(
                f"act() must give {n} finite joint targets (rad), got {targets.shape} at step {k}"
            )
        steering = np.asarray(ctrl.steering, dtype=float)
        if steering.shape != (2,) or not (np.abs(steering) <= 1.0).all():
            raise ControllerContractError(
                f"steering must be two numbers in [-1, 1], got {steering.tolist()} at step {k}"
            )
        row = [targets, steering.copy()]
        for key, shape in recorded.items():
            value = np.asarray(getattr(ctrl, key, None), dtype=float)
            if value.shape != shape:
                raise ControllerContractError(f"recorded {key!r} has shape {value.shape}, declared {shape}")
            row.append(value.copy())
        rows.append(row)
    return rows
