r"""Fixed points and hysteresis of the sensory network with frozen weights (paper Fig. 2).

One neuron with self connection b and input weight a: :math:`O = \tanh(bO + aI)`. Its fixed
points satisfy :math:`aI = \operatorname{atanh}(O) - bO`; a fixed point is stable where
:math:`b(1 - O^2) < 1`. For b <= 1 there is one fixed point for every input (near-linear
response, Fig. 2B); for b > 1 there are three between the switching inputs

.. math::

    I_\pm = \pm\,\bigl(bO^* - \operatorname{atanh}(O^*)\bigr)/a, \qquad O^* = \sqrt{1 - 1/b},

so the output switches on at :math:`I_+` and off at :math:`I_-`: a hysteresis of width
:math:`I_+ - I_-` that grows with b (Fig. 2C). Where :math:`I_+ > 1` the neuron cannot be switched
by any input in [-1, 1]: a two-state system (Fig. 2D).

For the two-neuron network the same question is answered numerically: the left input is swept
up from -1 to 1 and back while the right input is held (default -1, no obstacle), the network
settling at each input level; the switch-on and switch-off inputs are read off the sweep.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from neurowalk.compiled import jit
from neurowalk.neural.sensory import SensoryParams, initial_state, sensory_step

A_DEFAULT = SensoryParams().a  # input weight 4.7


def single_neuron_branches(b: float, a: float = A_DEFAULT, n: int = 801) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fixed-point curve of one neuron: (inputs I, outputs O, stable), each (n,).

    The curve is parametrised by O in (-1, 1); inputs outside [-1, 1] are kept so the caller can
    clip the view.
    """
    o = np.linspace(-1.0, 1.0, n + 2)[1:-1]
    i = (np.arctanh(o) - b * o) / a
    stable = b * (1.0 - o**2) < 1.0
    return i, o, stable


def single_neuron_thresholds(b: float, a: float = A_DEFAULT) -> tuple[float, float] | None:
    """Analytic switch-on and switch-off inputs (I_on, I_off) of one neuron; None for b <= 1."""
    if b <= 1.0:
        return None
    o_star = math.sqrt(1.0 - 1.0 / b)
    theta = b * o_star - math.atanh(o_star)
    return theta / a, -theta / a


@jit
def _sweep(s: np.ndarray, levels: np.ndarray, other: float, p: np.ndarray, settle: int, out: np.ndarray) -> None:
    for j in range(levels.shape[0]):
        for _ in range(settle):
            sensory_step(s, levels[j], other, p)
        out[j, 0] = s[0]
        out[j, 1] = s[1]


@dataclass(frozen=True)
class HysteresisLoop:
    """A measured up-then-down sweep of the left input.

    Attributes:
        levels: (n,) left input levels, going up from -1 to 1 then back down.
        outputs: (n, 2) settled outputs (O1, O2) at each level.
        switch_on: input at which O1 first turns positive going up (None: never).
        switch_off: input at which O1 first turns negative going down (None: stays on, latched).
    """

    levels: np.ndarray
    outputs: np.ndarray
    switch_on: float | None
    switch_off: float | None

    @property
    def width(self) -> float:
        """switch_on - switch_off (0: no hysteresis; inf: latched on; nan: never switched on)."""
        if self.switch_on is None:
            return math.nan
        if self.switch_off is None:
            return math.inf
        return self.switch_on - self.switch_off


def hysteresis_loop(
    b: float,
    c: float,
    *,
    other_input: float = -1.0,
    a: float = A_DEFAULT,
    n_levels: int = 201,
    settle: int = 60,
    single: bool = False,
) -> HysteresisLoop:
    """Sweep the left input of the network with frozen weights b (both neurons) and c <= 0.

    With ``single=True`` the right neuron is cut off (c = 0 and its output held at 0), which
    measures one neuron with self connection b.
    """
    if c > 0:
        raise ValueError(f"c is the inhibitory weight and must be <= 0, got {c!r}")
    up = np.linspace(-1.0, 1.0, n_levels)
    levels = np.concatenate([up, up[::-1]])
    p = SensoryParams(a=a).as_array(learning=False)
    q = 0.0 if single else -c
    s = initial_state(np.array([b, 0.0 if single else b]), np.array([q, q]), o0=(-1.0, -1.0))
    out = np.empty((levels.size, 2))
    _sweep(s, levels, other_input, p, settle, out)
    o1 = out[:, 0]
    switch_on = _crossing(up, o1[:n_levels], rising=True)
    switch_off = _crossing(up[::-1], o1[n_levels:], rising=False) if switch_on is not None else None
    return HysteresisLoop(levels=levels, outputs=out, switch_on=switch_on, switch_off=switch_off)


def _crossing(levels: np.ndarray, o: np.ndarray, *, rising: bool) -> float | None:
    """Input level where ``o`` first crosses 0 (upwards if ``rising``), linearly interpolated."""
    hit = np.flatnonzero(o > 0.0) if rising else np.flatnonzero(o < 0.0)
    if hit.size == 0:
        return None
    j = int(hit[0])
    if j == 0:
        return float(levels[0])
    frac = -o[j - 1] / (o[j] - o[j - 1])
    return float(levels[j - 1] + frac * (levels[j] - levels[j - 1]))


def hysteresis_width_map(b_values: np.ndarray, c_values: np.ndarray, **kwargs: object) -> np.ndarray:
    """Hysteresis width of the two-neuron network over a grid: shape (len(b_values), len(c_values))."""
    return np.array([[hysteresis_loop(b, c, **kwargs).width for c in c_values] for b in b_values])  # type: ignore[arg-type]
