r"""The adaptive sensory network: two recurrent neurons whose synapses learn online (DESIGN §3).

State at step t: outputs O(t), O(t-1) in [-1, 1]^2, self weights b(t), inhibition magnitudes
q(t) >= 0, input I(t) in [-1, 1]^2. Every right-hand side uses the values at t:

1. O(t+1) = tanh(b(t)∘O(t) + c(t)·(O2(t), O1(t)) + a·I(t)),  c(t) = -(q1(t) + q2(t))/2
2. nu = (O + 1)/2;  T(t) = 1 where I(t) > -0.5, else 0
3. b(t+1) = b(t) + mu_b·nu(t-1)·nu(t)·T(t) + gamma_b·(k - nu(t))·b(t)^2
4. q(t+1) = q(t) + mu_q·nu(t-1)·nu(t)·T(t) + gamma_q·(k - nu(t))·q(t)^2

Neuron 1 is the left one (left ultrasonic sensor, I1, O1), neuron 2 the right one. Modes:
``plastic`` (learning on; b = q = 0 at the start unless given), ``static`` (b = 2.4, c = -3.5,
the paper's hand-tuned network) and ``braitenberg`` (b = c = 0). The original code's details
(activity cut-off 0.009, reflex on US > 0.2, start b = 2, q = 3) and its ablations (learn b only,
learn q only) are options of :class:`SensoryParams`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numba import njit

from neurowalk.neural.plasticity import activity, correlation_scaling_delta, reflex_signal

Mode = Literal["plastic", "static", "braitenberg"]
MODES: tuple[str, ...] = ("plastic", "static", "braitenberg")

STATIC_B: float = 2.4  # self weight of the hand-tuned network (paper §2.1.1)
STATIC_Q: float = 3.5  # inhibition magnitude of the hand-tuned network: c = -3.5
ORIGINAL_B0: float = 2.0  # initial self weight in the authors' code
ORIGINAL_Q0: float = 3.0  # initial inhibition magnitude in the authors' code

US_NEAR_M: float = 0.05  # distance at which the input saturates at +1 (m)
US_RANGE_M: float = 0.40  # sensor range: at or beyond it (or no echo) the input is -1 (m)


@dataclass(frozen=True, kw_only=True)
class SensoryParams:
    """Parameters of the sensory network. Rates are per control step (dimensionless)."""

    a: float = 4.7  # input weight
    mu_b: float = 0.0065  # learning rate of the self weights b
    mu_q: float = 0.015  # learning rate of the inhibition magnitudes q
    gamma_b: float = 0.0003  # synaptic scaling rate of b
    gamma_q: float = 0.0003  # synaptic scaling rate of q
    k: float = -0.01  # scaling offset (negative: forgetting)
    reflex_threshold: float = -0.5  # T = 1 where I > threshold (-0.5: obstacle within ~0.3 m)
    activity_cutoff: float = 0.0  # activities nu below this are set to 0 (original code: 0.009)
    learn_b: bool = True  # plastic mode: learn b (False: b stays at its start, 2.4 by default)
    learn_q: bool = True  # plastic mode: learn q (False: q stays at its start, 3.5 by default)

    def __post_init__(self) -> None:
        for name in ("a", "mu_b", "mu_q", "gamma_b", "gamma_q", "k", "reflex_threshold"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"SensoryParams.{name} must be finite, got {getattr(self, name)!r}")
        for name in ("mu_b", "mu_q", "gamma_b", "gamma_q"):
            if getattr(self, name) < 0:
                raise ValueError(f"SensoryParams.{name} must be >= 0, got {getattr(self, name)!r}")
        if not 0.0 <= self.activity_cutoff < 1.0:
            raise ValueError(f"SensoryParams.activity_cutoff must be in [0, 1), got {self.activity_cutoff!r}")

    @classmethod
    def original_code(cls, **changes: float | bool) -> SensoryParams:
        """The authors' code: activity cut-off 0.009, reflex on US > 0.2 (I > -0.6)."""
        return cls(**{"activity_cutoff": 0.009, "reflex_threshold": -0.6, **changes})

    def as_array(self, learning: bool) -> np.ndarray:
        """Pack for the compiled step: (a, mu_b, mu_q, gamma_b, gamma_q, k, thr, cutoff, lb, lq)."""
        lb = float(learning and self.learn_b)
        lq = float(learning and self.learn_q)
        return np.array(
            [self.a, self.mu_b, self.mu_q, self.gamma_b, self.gamma_q, self.k,
             self.reflex_threshold, self.activity_cutoff, lb, lq]
        )  # fmt: skip


def initial_weights(
    mode: str, params: SensoryParams | None = None, b0: object = None, q0: object = None
) -> tuple[np.ndarray, np.ndarray]:
    """Start weights (b0, q0), each (2,), for ``mode``; explicit b0/q0 win where learning is on.

    Static and Braitenberg modes have fixed weights; passing b0/q0 for them is an error. In plastic
    mode a weight that is not learned (``learn_b``/``learn_q`` False) defaults to the static value.
    """
    if mode not in MODES:
        raise ValueError(f"unknown sensory mode {mode!r}; expected one of {MODES}")
    p = params or SensoryParams()
    if mode != "plastic":
        if b0 is not None or q0 is not None:
            raise ValueError(f"mode {mode!r} has fixed weights; b0/q0 apply to mode 'plastic' only")
        w = (STATIC_B, STATIC_Q) if mode == "static" else (0.0, 0.0)
        return np.full(2, w[0]), np.full(2, w[1])
    b_default = 0.0 if p.learn_b else STATIC_B
    q_default = 0.0 if p.learn_q else STATIC_Q
    b = _pair("b0", b_default if b0 is None else b0)
    q = _pair("q0", q_default if q0 is None else q0)
    if np.any(b < 0):
        raise ValueError(f"b0 must be >= 0 (self weights are excitatory), got {b.tolist()}")
    if np.any(q < 0):
        raise ValueError(f"q0 must be >= 0 (inhibition magnitudes), got {q.tolist()}")
    return b, q


def _pair(name: str, value: object) -> np.ndarray:
    """``value`` (a number or two) as a (2,) float array; raises ValueError naming ``name``."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(2, float(arr))
    if arr.shape != (2,):
        raise ValueError(f"{name} must be a number or have shape (2,), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {arr.tolist()}")
    return arr


def distance_to_input(distance_m: np.ndarray | float) -> np.ndarray:
    """Map ultrasonic distance (m) to network input: 1 at <= 0.05 m, -1 at >= 0.40 m or no echo.

    Linear in between. ``inf`` or NaN (no echo) and negative values (MuJoCo's "no hit") give -1.
    """
    d = np.asarray(distance_m, dtype=float)
    no_echo = ~np.isfinite(d) | (d < 0)
    x = 1.0 - 2.0 * (np.where(no_echo, US_RANGE_M, d) - US_NEAR_M) / (US_RANGE_M - US_NEAR_M)
    return np.clip(x, -1.0, 1.0)


@njit(cache=True)
def distance_input(distance_m: float) -> float:
    """Scalar, compiled :func:`distance_to_input` (the one used in every control loop)."""
    if not (distance_m >= 0.0) or math.isinf(distance_m):  # NaN, negative, inf: no echo
        return -1.0
    x = 1.0 - 2.0 * (distance_m - US_NEAR_M) / (US_RANGE_M - US_NEAR_M)
    return min(1.0, max(-1.0, x))


# State layout of one network: (o1, o2, o1(t-1), o2(t-1), b1, b2, q1, q2).
STATE_SIZE = 8


@njit(cache=True)
def sensory_step(s: np.ndarray, i1: float, i2: float, p: np.ndarray) -> None:
    """Advance one network by one step in place. ``s``: (8,) state; ``p``: params array."""
    o1, o2, op1, op2, b1, b2, q1, q2 = s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7]
    a = p[0]
    c = -0.5 * (q1 + q2)
    s[0] = math.tanh(b1 * o1 + c * o2 + a * i1)
    s[1] = math.tanh(b2 * o2 + c * o1 + a * i2)
    s[2] = o1
    s[3] = o2
    if p[8] > 0.0 or p[9] > 0.0:
        cut, k = p[7], p[5]
        nu1, nu2 = activity(o1, cut), activity(o2, cut)
        nup1, nup2 = activity(op1, cut), activity(op2, cut)
        t1, t2 = reflex_signal(i1, p[6]), reflex_signal(i2, p[6])
        if p[8] > 0.0:
            s[4] = b1 + correlation_scaling_delta(b1, nup1, nu1, t1, p[1], p[3], k)
            s[5] = b2 + correlation_scaling_delta(b2, nup2, nu2, t2, p[1], p[3], k)
        if p[9] > 0.0:
            s[6] = q1 + correlation_scaling_delta(q1, nup1, nu1, t1, p[2], p[4], k)
            s[7] = q2 + correlation_scaling_delta(q2, nup2, nu2, t2, p[2], p[4], k)


@njit(cache=True)
def _run(s: np.ndarray, inputs: np.ndarray, p: np.ndarray, out: np.ndarray) -> None:
    """Step over inputs (T, 2); row t of ``out`` (T, 8) is the state after the t-th update."""
    for t in range(inputs.shape[0]):
        sensory_step(s, inputs[t, 0], inputs[t, 1], p)
        out[t] = s


@njit(cache=True)
def sensory_step_batch(s: np.ndarray, inputs: np.ndarray, p: np.ndarray) -> None:
    """Advance n networks one step in place: ``s`` (n, 8), ``inputs`` (n, 2)."""
    for i in range(s.shape[0]):
        sensory_step(s[i], inputs[i, 0], inputs[i, 1], p)


@dataclass(frozen=True)
class SensoryTrace:
    """Result of :func:`simulate`: row t holds the values after the t-th update from inputs[t].

    Attributes:
        inputs: (T, 2) the inputs I(t).
        outputs: (T, 2) outputs O(t+1).
        b: (T, 2) self weights b(t+1).
        q: (T, 2) inhibition magnitudes q(t+1) >= 0.
        mode: the mode simulated.
    """

    inputs: np.ndarray
    outputs: np.ndarray
    b: np.ndarray
    q: np.ndarray
    mode: str

    @property
    def c(self) -> np.ndarray:
        """(T,) shared inhibitory weight c = -(q1 + q2)/2 (negative)."""
        return -0.5 * (self.q[:, 0] + self.q[:, 1])


def validate_inputs(inputs: object) -> np.ndarray:
    """Return ``inputs`` as a (T, 2) float array, or raise ValueError naming what is wrong."""
    x = np.asarray(inputs, dtype=float)
    if x.ndim != 2 or x.shape[1] != 2 or x.shape[0] < 1:
        raise ValueError(f"inputs must have shape (T, 2) with T >= 1, got shape {x.shape}")
    bad = ~np.isfinite(x)
    if bad.any():
        t = int(np.argwhere(bad)[0, 0])
        raise ValueError(f"inputs must be finite; row {t} is {x[t].tolist()}")
    out = (x < -1.0) | (x > 1.0)
    if out.any():
        t = int(np.argwhere(out)[0, 0])
        raise ValueError(f"inputs must lie in [-1, 1]; row {t} is {x[t].tolist()}")
    return np.ascontiguousarray(x)


def initial_state(b0: np.ndarray, q0: np.ndarray, o0: object = (0.0, 0.0)) -> np.ndarray:
    """Packed (8,) start state with O(-1) = O(0) = o0."""
    o = _pair("o0", o0)
    if np.any(np.abs(o) > 1.0):
        raise ValueError(f"o0 must lie in [-1, 1], got {o.tolist()}")
    return np.concatenate([o, o, b0, q0])


def simulate(
    inputs: object,
    *,
    mode: Mode = "plastic",
    b0: object = None,
    q0: object = None,
    o0: object = (0.0, 0.0),
    params: SensoryParams | None = None,
) -> SensoryTrace:
    """Run the sensory network over a sequence of inputs.

    Args:
        inputs: (T, 2) inputs (I1 left, I2 right), each in [-1, 1], one row per control step.
        mode: ``plastic``, ``static`` or ``braitenberg``.
        b0: start self weights, number or (2,); plastic mode only (default: 0).
        q0: start inhibition magnitudes >= 0, number or (2,); plastic mode only (default: 0).
        o0: start outputs O(-1) = O(0), (2,) in [-1, 1].
        params: network parameters (default :class:`SensoryParams`).

    Returns:
        A :class:`SensoryTrace`; row t of each array is the state after the update from inputs[t].

    Raises:
        ValueError: wrong shapes, non-finite or out-of-range values, unknown mode.
    """
    x = validate_inputs(inputs)
    p = params or SensoryParams()
    b, q = initial_weights(mode, p, b0, q0)
    s = initial_state(b, q, o0)
    out = np.empty((x.shape[0], STATE_SIZE))
    _run(s, x, p.as_array(mode == "plastic"), out)
    return SensoryTrace(inputs=x, outputs=out[:, 0:2].copy(), b=out[:, 4:6].copy(),
                        q=out[:, 6:8].copy(), mode=mode)  # fmt: skip


class SensoryNetwork:
    """Stateful holder of one sensory network, for closed-loop use (one step per control step)."""

    def __init__(
        self,
        mode: Mode = "plastic",
        *,
        params: SensoryParams | None = None,
        b0: object = None,
        q0: object = None,
    ) -> None:
        self.mode = mode
        self.params = params or SensoryParams()
        self._b0, self._q0 = initial_weights(mode, self.params, b0, q0)
        self._p = self.params.as_array(mode == "plastic")
        self.state = initial_state(self._b0, self._q0)

    def reset(self) -> None:
        """Back to the start weights, with outputs 0."""
        self.state = initial_state(self._b0, self._q0)

    def step(self, i1: float, i2: float) -> tuple[float, float]:
        """One update from inputs (I1, I2) in [-1, 1]; returns the new outputs (O1, O2)."""
        sensory_step(self.state, i1, i2, self._p)
        return self.state[0], self.state[1]

    @property
    def packed_params(self) -> np.ndarray:
        """The params array of :func:`sensory_step` (for compiled loops that step :attr:`state` in place)."""
        return self._p

    @property
    def b(self) -> np.ndarray:
        """(2,) current self weights."""
        return self.state[4:6].copy()

    @property
    def q(self) -> np.ndarray:
        """(2,) current inhibition magnitudes."""
        return self.state[6:8].copy()
