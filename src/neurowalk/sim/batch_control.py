"""The controllers of many runs, stepped together: one compiled call per control step for all copies.

:class:`BatchControllers` packs the state of each copy's :class:`~neurowalk.controller.NeuralController` or
:class:`~neurowalk.controller.FixedController` into ``(n, ...)`` arrays and steps them all in one numba loop
that calls the single loop's own kernels (:func:`~neurowalk.neural.sensory.sensory_step`,
:func:`~neurowalk.neural.motor.locomotion_step`), so copy i computes exactly what its controller's ``act``
would, bit for bit. Any other controller (a user's, a network with a user's learning rule, or copies whose delay
lines differ in length) goes through its own ``act``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from neurowalk import anatomy
from neurowalk.compiled import jit
from neurowalk.controller import Controller, FixedController, NeuralController, recorded_state
from neurowalk.neural.motor import locomotion_step
from neurowalk.neural.sensory import STEER, sensory_input, sensory_step
from neurowalk.observation import Observation

FIXED, NEURAL = 0, 1  # kinds of copy in the compiled step


@jit
def control_step(
    kind: np.ndarray,
    dist: np.ndarray,
    sens: np.ndarray,
    sens_p: np.ndarray,
    loc: np.ndarray,
    buf: np.ndarray,
    loc_p: np.ndarray,
    inputs: np.ndarray,
    outputs: np.ndarray,
    targets: np.ndarray,
) -> None:
    """One control step of n controllers, in place.

    Args:
        kind: (n,) FIXED or NEURAL. dist: (n, 2) ultrasonic distances (m, inf = no echo).
        sens: (n, STATE_SIZE) sensory network states. sens_p: (n, P) their packed params.
        loc: (n, S) locomotion network states. buf: (n, L, 5) their delay lines. loc_p: (n, 8) packed params.
        inputs: (n, 2) out, network inputs (I1, I2). outputs: (n, 2) steering (O1, O2); for FIXED copies it is
            read (the fixed steering). targets: (n, 19) out, joint targets (rad, actuator order; BJ stays as is).
    """
    for i in range(kind.shape[0]):
        if kind[i] == NEURAL:
            i1 = sensory_input(dist[i, 0], sens_p[i])
            i2 = sensory_input(dist[i, 1], sens_p[i])
            sensory_step(sens[i], i1, i2, sens_p[i])
            inputs[i, 0], inputs[i, 1] = i1, i2
            outputs[i, 0], outputs[i, 1] = sens[i, STEER], sens[i, STEER + 1]
        locomotion_step(loc[i], buf[i], outputs[i, 0], outputs[i, 1], loc_p[i], targets[i])


class BatchControllers:
    """n controllers behind one step call.

    Attributes:
        inputs: (n, 2) last network inputs (I1, I2); -1 for a fixed controller.
        outputs: (n, 2) last steering (O1, O2).
        b, q: (n, 2) sensory weights after the last step (NaN for a fixed controller).
        targets: (n, 19) last joint targets (rad, actuator order).
        recorded: the controllers' declared state (``Controller.recorded``: name -> a row's shape; the same for
            every copy). state: name -> (n, ...) its values after the last step.
        compiled: whether the compiled step serves every copy (else each controller's ``act``).
    """

    def __init__(self, controllers: Sequence[Controller], *, compiled: bool = True) -> None:
        self.controllers = list(controllers)
        n = len(self.controllers)
        known = all(_built_in(c) for c in self.controllers)
        lengths = {c.locomotion.params.buffer_length for c in self.controllers} if known else set()  # type: ignore[attr-defined]
        self.compiled = compiled and known and len(lengths) == 1
        self.has_weights = np.array([hasattr(c, "b") for c in self.controllers])
        self._weights = self.has_weights.tolist()  # (as Python bools: read every step)
        self._has_inputs = [hasattr(c, "inputs") for c in self.controllers]
        self.inputs = np.zeros((n, 2))
        self.outputs = np.zeros((n, 2))
        self.b = np.full((n, 2), np.nan)
        self.q = np.full((n, 2), np.nan)
        self.targets = np.zeros((n, anatomy.N_ACTUATORS))
        declared = [recorded_state(c) for c in self.controllers]
        if any(d != declared[0] for d in declared):
            raise ValueError("the controllers of one batch declare different recorded state")
        self.recorded = declared[0] if declared else {}
        self.state = {k: np.full((n, *shape), np.nan) for k, shape in self.recorded.items()}

    def reset(self, rngs: Sequence[np.random.Generator | None]) -> None:
        """Reset every controller with its run's Generator, then pack the start states."""
        for c, rng in zip(self.controllers, rngs, strict=True):
            c.reset(rng)
        if self.compiled:
            neural = [c for c in self.controllers if isinstance(c, NeuralController)]
            width = len(neural[0].sensory.state) if neural else 14
            n_p = len(neural[0].sensory.params.as_array(True)) if neural else 1
            n = len(self.controllers)
            self._kind = np.array([NEURAL if isinstance(c, NeuralController) else FIXED for c in self.controllers])
            self._neural = np.flatnonzero(self._kind == NEURAL)
            self._sens = np.zeros((n, width))
            self._sens_p = np.zeros((n, n_p))
            locs = [c.locomotion for c in self.controllers]  # type: ignore[attr-defined]
            self._loc = np.stack([net.state for net in locs])
            self._buf = np.stack([net.buffer for net in locs])
            self._loc_p = np.zeros((n, len(locs[0].params.as_array())))
        for i in range(len(self.controllers)):
            self._pack(i)

    def reset_copy(self, i: int, rng: np.random.Generator | None = None) -> None:
        """Reset copy i's controller alone (with ``rng``, as :meth:`reset` does) and pack its start state.

        The other copies go on where they are; call :meth:`reset` once before (it sizes the packed arrays).
        """
        self.controllers[i].reset(rng)
        self._pack(i)

    def _pack(self, i: int) -> None:
        """Copy i's controller state (just reset) into the batch arrays."""
        c = self.controllers[i]
        self.targets[i] = 0.0
        self.inputs[i] = getattr(c, "inputs", np.zeros(2))
        self.outputs[i] = c.steering
        if not self.compiled:
            return
        if isinstance(c, NeuralController):
            self._sens[i] = c.sensory.state
            self._sens_p[i] = c.sensory.params.as_array(c.sensory.mode == "plastic")
        net = c.locomotion  # type: ignore[attr-defined]
        self._loc[i], self._buf[i], self._loc_p[i] = net.state, net.buffer, net.params.as_array()

    def compiled_parts(self, i: int) -> tuple[tuple[np.ndarray, np.ndarray] | None, np.ndarray | None]:
        """Copy i's controller as a body compiled with it steps it (the planar surrogate): its sensory network's
        state (advanced in place) and packed params, or its constant steering pair (O1, O2); (None, None) for a
        controller stepped by ``act``."""
        c = self.controllers[i]
        if not _built_in(c):
            return None, None
        if isinstance(c, NeuralController):
            return (c.sensory.state, c.sensory.packed_params), None
        if isinstance(c, FixedController):
            return None, np.asarray(c.steering, dtype=float)
        return None, None

    def step(self, dist: np.ndarray, observe: Callable[[int], Observation] | None = None) -> np.ndarray:
        """One control step of every copy; returns the (n, 19) targets (the internal buffer).

        Args:
            dist: (n, 2) ultrasonic distances the controllers see (m, inf = no echo).
            observe: ``observe(i)`` -> copy i's full observation, for controllers stepped by ``act``.
        """
        if self.compiled:
            control_step(
                self._kind,
                dist,
                self._sens,
                self._sens_p,
                self._loc,
                self._buf,
                self._loc_p,
                self.inputs,
                self.outputs,
                self.targets,
            )
            neural = self._neural
            if neural.size:
                self.b[neural] = self._sens[neural, 4:6]
                self.q[neural] = self._sens[neural, 6:8]
            return self.targets
        if observe is None:
            raise ValueError("controllers stepped by act() need the full observations")
        for i, c in enumerate(self.controllers):
            self.targets[i] = c.act(observe(i))
            self.inputs[i] = c.inputs if self._has_inputs[i] else np.nan
            self.outputs[i] = c.steering
            if self._weights[i]:
                self.b[i] = c.b  # type: ignore[attr-defined]
                self.q[i] = c.q  # type: ignore[attr-defined]
            for k, a in self.state.items():
                a[i] = getattr(c, k)
        return self.targets


def _built_in(c: Controller) -> bool:
    """A built-in controller with the built-in network step: the compiled kernels step it."""
    return isinstance(c, FixedController) or (isinstance(c, NeuralController) and c.sensory.rule is None)
