r"""The adaptive sensory network: two recurrent neurons whose synapses learn online (DESIGN §3).

State at step t: outputs O(t), O(t-1) in [-1, 1]^2, self weights b(t), inhibition magnitudes
q(t) >= 0, input I(t) in [-1, 1]^2. Every right-hand side uses the values at t:

1. O(t+1) = tanh(b(t)∘O(t) + c(t)·(O2(t), O1(t)) + a·I(t)),  c(t) = -(q1(t) + q2(t))/2
2. nu = (O + 1)/2;  T(t) = 1 where I(t) > -0.5, else 0
3. b(t+1) = b(t) + mu_b·nu(t-1)·nu(t)·T(t) + gamma_b·(k - nu(t))·b(t)^2
4. q(t+1) = q(t) + mu_q·nu(t-1)·nu(t)·T(t) + gamma_q·(k - nu(t))·q(t)^2

Neuron 1 is the left one (left ultrasonic sensor, I1, O1), neuron 2 the right one. Modes:
``plastic`` (learning on; b = q = 0 at the start unless given), ``static`` (b = 2.4, c = -3.5,
the paper's hand-tuned network) and ``braitenberg`` (b = c = 0). The ablations (learn b only,
learn q only) and the authors' code's timing and details are options of :class:`SensoryParams`:
:meth:`SensoryParams.original_code` gives the network as the authors' code runs it (see
:mod:`neurowalk.neural.variants` and ``docs/paper-vs-code.md``): the input passes an identity neuron
(the network sees the previous reading), the weights learn from the activities before and after the
update, the steering leaves through two more identity layers (3 control steps from reading to
steering), the constructor's step with zero input (which does not learn), I = 1 - 2d/0.4, start b = 2, q = 3, activity
cut-off 0.009, reflex gate on US > 0.2.

The state of one network is a flat (14,) array (:data:`STATE_SIZE`), the steering it sends to the
locomotion network in slots 8-9 (:data:`STEER`): the new outputs, or older ones with a steering delay.
"""

from __future__ import annotations

import math
import reprlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np

from neurowalk.compiled import jit
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
    """Parameters of the sensory network (Eq. 1-6). Rates are per control step (dimensionless).

    Attributes:
        a: input weight.
        mu_b: learning rate of the self weights b.
        mu_q: learning rate of the inhibition magnitudes q.
        gamma_b: synaptic scaling rate of b.
        gamma_q: synaptic scaling rate of q.
        k: scaling offset (negative: forgetting).
        reflex_threshold: T = 1 where I > threshold (-0.5: obstacle within ~0.3 m).
        activity_cutoff: activities nu below this are set to 0 (original code: 0.009).
        learn_b: plastic mode: learn b (False: b stays at its start, 2.4 by default).
        learn_q: plastic mode: learn q (False: q stays at its start, 3.5 by default).
        us_near: distance (m) at or below which the input is +1 (original code: 0).
        input_delay: the input passes an identity neuron: the network sees the last step's reading.
        post_learning: learn from nu(O before the update), nu(O after it) instead of nu(t-1), nu(t).
        steer_delay: control steps between a new output and the steering it sends (0, 1 or 2).
        prime_step: at reset, one step with zero input, no learning (the original's constructor).
        b_start: plastic start self weights (None: 0, or 2.4 if b is not learned).
        q_start: plastic start inhibition magnitudes (None: 0, or 3.5 if q is not learned).
    """

    a: float = 4.7
    mu_b: float = 0.0065
    mu_q: float = 0.015
    gamma_b: float = 0.0003
    gamma_q: float = 0.0003
    k: float = -0.01
    reflex_threshold: float = -0.5
    activity_cutoff: float = 0.0
    learn_b: bool = True
    learn_q: bool = True
    us_near: float = US_NEAR_M
    input_delay: bool = False
    post_learning: bool = False
    steer_delay: int = 0
    prime_step: bool = False
    b_start: float | None = None
    q_start: float | None = None

    def __post_init__(self) -> None:
        for name in ("a", "mu_b", "mu_q", "gamma_b", "gamma_q", "k", "reflex_threshold"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"SensoryParams.{name} must be finite, got {getattr(self, name)!r}")
        for name in ("mu_b", "mu_q", "gamma_b", "gamma_q"):
            if getattr(self, name) < 0:
                raise ValueError(f"SensoryParams.{name} must be >= 0, got {getattr(self, name)!r}")
        if not 0.0 <= self.activity_cutoff < 1.0:
            raise ValueError(f"SensoryParams.activity_cutoff must be in [0, 1), got {self.activity_cutoff!r}")
        if not (math.isfinite(self.us_near) and 0.0 <= self.us_near < US_RANGE_M):
            raise ValueError(f"SensoryParams.us_near must be in [0, {US_RANGE_M}) m, got {self.us_near!r}")
        if self.steer_delay not in (0, 1, 2):
            raise ValueError(f"SensoryParams.steer_delay must be 0, 1 or 2 control steps, got {self.steer_delay!r}")
        for name in ("b_start", "q_start"):
            v = getattr(self, name)
            if v is not None and not (math.isfinite(v) and v >= 0):
                raise ValueError(f"SensoryParams.{name} must be a finite number >= 0, got {v!r}")

    @classmethod
    def original_code(cls, **changes: float | bool) -> SensoryParams:
        """The network as the authors' code runs it (``docs/paper-vs-code.md``, all points).

        Input I = 1 - 2d/0.4 (``us_near`` 0) through an identity neuron (``input_delay``), learning from
        the activities before and after the update (``post_learning``), steering through two more identity
        layers (``steer_delay`` 2), the constructor's zero-input step (``prime_step``), start b = 2, q = 3,
        activity cut-off 0.009, reflex gate on US > 0.2 (I > -0.6).
        """
        base: dict[str, float | bool | int | None] = {
            "activity_cutoff": 0.009,
            "reflex_threshold": -0.6,
            "us_near": 0.0,
            "input_delay": True,
            "post_learning": True,
            "steer_delay": 2,
            "prime_step": True,
            "b_start": ORIGINAL_B0,
            "q_start": ORIGINAL_Q0,
        }
        return cls(**{**base, **changes})  # type: ignore[arg-type]

    def as_array(self, learning: bool) -> np.ndarray:
        """Pack for the compiled step (:data:`PARAMS_SIZE` values, see :func:`sensory_step`)."""
        lb = float(learning and self.learn_b)
        lq = float(learning and self.learn_q)
        return np.array(
            [
                self.a,
                self.mu_b,
                self.mu_q,
                self.gamma_b,
                self.gamma_q,
                self.k,
                self.reflex_threshold,
                self.activity_cutoff,
                lb,
                lq,
                self.us_near,
                float(self.input_delay),
                float(self.post_learning),
                float(self.steer_delay),
            ]
        )


def initial_weights(
    mode: str, params: SensoryParams | None = None, b0: object = None, q0: object = None
) -> tuple[np.ndarray, np.ndarray]:
    """Start weights (b0, q0), each (2,), for ``mode``; explicit b0/q0 win where learning is on.

    Static and Braitenberg modes have fixed weights; passing b0/q0 for them is an error. In plastic
    mode a weight that is not learned (``learn_b``/``learn_q`` False) defaults to the static value.
    """
    if mode not in MODES:
        raise ValueError(f"unknown sensory mode {mode!r}; expected one of {MODES}")
    p = checked_params(params)
    if mode != "plastic":
        if b0 is not None or q0 is not None:
            raise ValueError(f"mode {mode!r} has fixed weights; b0/q0 apply to mode 'plastic' only")
        w = (STATIC_B, STATIC_Q) if mode == "static" else (0.0, 0.0)
        return np.full(2, w[0]), np.full(2, w[1])
    b_default = p.b_start if p.b_start is not None else (0.0 if p.learn_b else STATIC_B)
    q_default = p.q_start if p.q_start is not None else (0.0 if p.learn_q else STATIC_Q)
    b = _pair("b0", b_default if b0 is None else b0)
    q = _pair("q0", q_default if q0 is None else q0)
    if np.any(b < 0):
        raise ValueError(f"b0 must be >= 0 (self weights are excitatory), got {b.tolist()}")
    if np.any(q < 0):
        raise ValueError(f"q0 must be >= 0 (inhibition magnitudes), got {q.tolist()}")
    return b, q


def checked_params(params: object) -> SensoryParams:
    """``params``, or the defaults where it is None; TypeError naming anything else."""
    if params is not None and not isinstance(params, SensoryParams):
        raise TypeError(f"params must be a SensoryParams (None: the defaults), got {reprlib.repr(params)}")
    return params or SensoryParams()


def _floats(name: str, value: object, what: str) -> np.ndarray:
    """``value`` as a float array; ValueError naming it where it is not ``what`` (numbers in a regular shape)."""
    try:
        return np.asarray(value, dtype=float)
    except (ValueError, TypeError, OverflowError):
        raise ValueError(f"{name} must be {what}, got {reprlib.repr(value)}") from None


def _pair(name: str, value: object) -> np.ndarray:
    """``value`` (a number or two) as a (2,) float array; raises ValueError naming ``name``."""
    arr = _floats(name, value, "a number or two")
    if arr.ndim == 0:
        arr = np.full(2, float(arr))
    if arr.shape != (2,):
        raise ValueError(f"{name} must be a number or have shape (2,), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {arr.tolist()}")
    return arr


def distance_to_input(distance_m: np.ndarray | float, near: float = US_NEAR_M) -> np.ndarray:
    """Map ultrasonic distance (m) to network input: 1 at <= ``near`` m, -1 at >= 0.40 m or no echo.

    Linear in between (``near`` 0.05 m by default; 0 in the authors' code: I = 1 - 2d/0.4). ``inf`` or NaN
    (no echo) and negative values (MuJoCo's "no hit") give -1.
    """
    d = np.asarray(distance_m, dtype=float)
    no_echo = ~np.isfinite(d) | (d < 0)
    x = 1.0 - 2.0 * (np.where(no_echo, US_RANGE_M, d) - near) / (US_RANGE_M - near)
    return np.clip(x, -1.0, 1.0)


@jit
def distance_input(distance_m: float, near: float = US_NEAR_M) -> float:
    """Scalar, compiled :func:`distance_to_input` (the one used in every control loop)."""
    if not (distance_m >= 0.0) or math.isinf(distance_m):  # NaN, negative, inf: no echo
        return -1.0
    x = 1.0 - 2.0 * (distance_m - near) / (US_RANGE_M - near)
    return min(1.0, max(-1.0, x))


@jit
def sensory_input(distance_m: float, p: np.ndarray) -> float:
    """:func:`distance_input` with the near distance of a packed params array ``p``."""
    return distance_input(distance_m, p[10])


# State layout of one network: (o1, o2, o1(t-1), o2(t-1), b1, b2, q1, q2, steer1, steer2, x1, x2, o1(t-2),
# o2(t-2)): outputs, weights, the steering sent on, the input neuron's outputs, older outputs.
STATE_SIZE = 14
STEER = 8  # first steering slot
PARAMS_SIZE = 14


@jit
def sensory_step(s: np.ndarray, i1: float, i2: float, p: np.ndarray) -> None:
    """Advance one network by one step in place. ``s``: (14,) state; ``p``: (14,) packed params.

    ``p`` = (a, mu_b, mu_q, gamma_b, gamma_q, k, reflex threshold, activity cut-off, learn b, learn q,
    us_near, input delay, post learning, steer delay). With an input delay the new readings (i1, i2) are
    stored and last step's drive the neurons and the reflex gate.
    """
    if p[11] > 0.0:
        x1, x2 = s[10], s[11]
        s[10], s[11] = i1, i2
        i1, i2 = x1, x2
    o1, o2, op1, op2, b1, b2, q1, q2 = s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7]
    a = p[0]
    c = -0.5 * (q1 + q2)
    s[0] = math.tanh(b1 * o1 + c * o2 + a * i1)
    s[1] = math.tanh(b2 * o2 + c * o1 + a * i2)
    s[2] = o1
    s[3] = o2
    s[12] = op1
    s[13] = op2
    delay = p[13]
    if delay == 0.0:
        s[8], s[9] = s[0], s[1]
    elif delay == 1.0:
        s[8], s[9] = o1, o2
    else:
        s[8], s[9] = op1, op2
    if p[8] > 0.0 or p[9] > 0.0:
        cut, k = p[7], p[5]
        if p[12] > 0.0:  # the original: activities before and after this update
            nup1, nup2 = activity(o1, cut), activity(o2, cut)
            nu1, nu2 = activity(s[0], cut), activity(s[1], cut)
        else:  # Eq. 3-4: nu(t-1), nu(t)
            nu1, nu2 = activity(o1, cut), activity(o2, cut)
            nup1, nup2 = activity(op1, cut), activity(op2, cut)
        t1, t2 = reflex_signal(i1, p[6]), reflex_signal(i2, p[6])
        if p[8] > 0.0:
            s[4] = b1 + correlation_scaling_delta(b1, nup1, nu1, t1, p[1], p[3], k)
            s[5] = b2 + correlation_scaling_delta(b2, nup2, nu2, t2, p[1], p[3], k)
        if p[9] > 0.0:
            s[6] = q1 + correlation_scaling_delta(q1, nup1, nu1, t1, p[2], p[4], k)
            s[7] = q2 + correlation_scaling_delta(q2, nup2, nu2, t2, p[2], p[4], k)


@jit
def _run(s: np.ndarray, inputs: np.ndarray, p: np.ndarray, out: np.ndarray) -> None:
    """Step over inputs (T, 2); row t of ``out`` (T, STATE_SIZE) is the state after the t-th update."""
    for t in range(inputs.shape[0]):
        sensory_step(s, inputs[t, 0], inputs[t, 1], p)
        out[t] = s


@dataclass(frozen=True)
class SensoryTrace:
    """Result of :func:`simulate`: row t holds the values after the t-th update from inputs[t].

    Attributes:
        inputs: (T, 2) the inputs I(t).
        outputs: (T, 2) outputs O(t+1).
        b: (T, 2) self weights b(t+1).
        q: (T, 2) inhibition magnitudes q(t+1) >= 0.
        mode: the mode simulated.
        steering: (T, 2) the steering sent to the locomotion network (``outputs`` unless the params
            delay it).
    """

    inputs: np.ndarray
    outputs: np.ndarray
    b: np.ndarray
    q: np.ndarray
    mode: str
    steering: np.ndarray | None = None

    @property
    def c(self) -> np.ndarray:
        """(T,) shared inhibitory weight c = -(q1 + q2)/2 (negative)."""
        return -0.5 * (self.q[:, 0] + self.q[:, 1])


def validate_inputs(inputs: object) -> np.ndarray:
    """Return ``inputs`` as a (T, 2) float array, or raise ValueError naming what is wrong."""
    x = _floats("inputs", inputs, "a (T, 2) array of numbers (rows of equal length)")
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


def initial_state(
    b0: np.ndarray, q0: np.ndarray, o0: object = (0.0, 0.0), prime: np.ndarray | None = None
) -> np.ndarray:
    """Packed (STATE_SIZE,) start state with O(-2) = O(-1) = O(0) = o0, steering o0, input neurons 0.

    ``prime``: a packed params array to run the original's constructor step with (zero input; the neurons,
    input neurons and steering move, the weights do not learn: in the authors' code the learning rule lives in
    the obstacle-avoidance step, not in the network's step); None (default): no such step.
    """
    o = _pair("o0", o0)
    if np.any(np.abs(o) > 1.0):
        raise ValueError(f"o0 must lie in [-1, 1], got {o.tolist()}")
    s = np.concatenate([o, o, b0, q0, o, np.zeros(2), o])
    if prime is not None:
        no_learning = prime.copy()
        no_learning[8] = no_learning[9] = 0.0  # learn b, learn q off for this step only
        sensory_step(s, 0.0, 0.0, no_learning)
    return s


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
        ValueError: wrong shapes, ragged or non-numeric, non-finite or out-of-range values, unknown mode.
        TypeError: ``params`` that is not a :class:`SensoryParams`.
    """
    x = validate_inputs(inputs)
    p = checked_params(params)
    b, q = initial_weights(mode, p, b0, q0)
    packed = p.as_array(mode == "plastic")
    s = initial_state(b, q, o0, packed if p.prime_step else None)
    out = np.empty((x.shape[0], STATE_SIZE))
    _run(s, x, packed, out)
    return SensoryTrace(
        inputs=x,
        outputs=out[:, 0:2].copy(),
        b=out[:, 4:6].copy(),
        q=out[:, 6:8].copy(),
        mode=mode,
        steering=out[:, STEER : STEER + 2].copy(),
    )


class SensoryNetwork:
    """Stateful holder of one sensory network, for closed-loop use (one step per control step).

    ``rule``: the step, ``rule(state, i1, i2, packed params)`` in place as :func:`sensory_step` (a user's learning
    rule); None: :func:`sensory_step` itself, which compiled loops then call directly.
    """

    def __init__(
        self,
        mode: Mode = "plastic",
        *,
        params: SensoryParams | None = None,
        b0: object = None,
        q0: object = None,
        rule: Callable[[np.ndarray, float, float, np.ndarray], None] | None = None,
    ) -> None:
        self.mode = mode
        self.rule = rule
        self._step = sensory_step if rule is None else rule
        self.params = checked_params(params)
        self._b0, self._q0 = initial_weights(mode, self.params, b0, q0)
        self._p = self.params.as_array(mode == "plastic")
        self.reset()

    def reset(self) -> None:
        """Back to the start weights, with outputs 0 (and the constructor's step, where the params ask for it)."""
        self.state = initial_state(self._b0, self._q0, prime=self._p if self.params.prime_step else None)

    def step(self, i1: float, i2: float) -> tuple[float, float]:
        """One update from inputs (I1, I2) in [-1, 1]; returns the steering it sends on (O1, O2).

        The steering is the new outputs, or older ones where the params have a steering delay.
        """
        self._step(self.state, i1, i2, self._p)
        return self.state[STEER], self.state[STEER + 1]

    def input(self, distance_m: float) -> float:
        """Network input of an ultrasonic distance (m; inf = no echo), with these params' near distance."""
        return distance_input(distance_m, self.params.us_near)

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
