r"""SO(2)-type central pattern generator with modulatory input, and its post-processing (PCPG).

CPG (two tanh neurons, no biases): :math:`o(t+1) = \tanh(W o(t))` with

.. math::

    W = \begin{pmatrix} w_s & w_c + MI \\ -(w_c + MI) & w_s \end{pmatrix},\quad w_s = 1.4,\ w_c = 0.18

The modulatory input MI sets the frequency (MI = 0.03: period about 87.5 control steps, the slow
wave gait used throughout the paper). Start o = (0.1, 0.1).

PCPG, per channel: s = +1 where the CPG output is >= 0.85, else -1; the steps of the current
phase are counted (n), the lengths of the last completed up and down phases kept (D_up, D_dn);
the output is the sawtooth 2·n/D_up - 1 while up and -2·n/D_dn + 1 while down, clipped to
[-1, 1]. Before a full phase has been measured the output sits at ±1; the authors' code stores the
first, partial phase too (``pcpg_first_partial``), so its legs differ for the first ~250 steps.
For MI = 0.03 it rises in about 14.5 steps and falls in about 73: the fast rise becomes the swing,
about 1/6 of the cycle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from neurowalk.compiled import jit

GAITS: dict[str, float] = {
    "slow-wave": 0.02,
    "wave": 0.03,
    "slow-tetrapod": 0.05,
    "tetrapod": 0.14,
    "tripod": 0.18,
    "fast": 0.34,
}
"""Modulatory input MI of each named gait (the original code's list; ``wave`` is the default)."""


@dataclass(frozen=True, kw_only=True)
class CpgParams:
    """CPG and PCPG parameters (weights dimensionless; time in control steps)."""

    mi: float = GAITS["wave"]  # modulatory input MI
    w_self: float = 1.4  # self connection of each CPG neuron
    w_cross: float = 0.18  # cross connection without MI
    start: float = 0.1  # initial output of both neurons
    pcpg_threshold: float = 0.85  # CPG output at or above which a PCPG channel is "up"
    pcpg_first_partial: bool = False  # store the first, partial phase's length too (the authors' code)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.mi) and 0.0 <= self.mi < 1.0):
            raise ValueError(f"CpgParams.mi must be in [0, 1), got {self.mi!r}")
        if not -1.0 < self.pcpg_threshold < 1.0:
            raise ValueError(f"CpgParams.pcpg_threshold must be in (-1, 1), got {self.pcpg_threshold!r}")

    @classmethod
    def for_gait(cls, gait: str) -> CpgParams:
        """Parameters of a named gait (see :data:`GAITS`)."""
        if gait not in GAITS:
            raise ValueError(f"unknown gait {gait!r}; expected one of {tuple(GAITS)}")
        return cls(mi=GAITS[gait])


# PCPG channel state: (s, n_up, n_dn, D_up, D_dn, y, transitions seen).
PCPG_FIELDS = 7


@jit
def cpg_step(o: np.ndarray, w_self: float, w_cross: float) -> None:
    """Advance the CPG outputs ``o`` (2,) one step in place; ``w_cross`` includes MI."""
    o0, o1 = o[0], o[1]
    o[0] = math.tanh(w_self * o0 + w_cross * o1)
    o[1] = math.tanh(-w_cross * o0 + w_self * o1)


@jit
def pcpg_step(c: np.ndarray, act: float, threshold: float, partial: bool = False) -> float:
    """Advance one PCPG channel ``c`` (7,) in place from CPG output ``act``; returns y in [-1, 1].

    ``partial``: also store the length of the first phase, which began at the start, not at a transition.
    """
    s = 1.0 if act >= threshold else -1.0
    if s != c[0]:
        if c[6] >= 1.0 or partial:  # a full phase (it began at a transition), or any phase
            if c[0] > 0.0:
                c[3] = c[1]
            else:
                c[4] = c[2]
        if c[0] != 0.0:
            c[6] += 1.0
        c[0] = s
        c[1] = 0.0
        c[2] = 0.0
    if s > 0.0:
        c[1] += 1.0
        y = 2.0 * c[1] / c[3] - 1.0 if c[3] > 0.0 else 1.0
    else:
        c[2] += 1.0
        y = -2.0 * c[2] / c[4] + 1.0 if c[4] > 0.0 else -1.0
    y = min(1.0, max(-1.0, y))
    c[5] = y
    return y


@jit
def _run_cpg(
    o: np.ndarray, pc: np.ndarray, steps: int, w_self: float, w_cross: float, thr: float, partial: bool, out: np.ndarray
) -> None:
    for t in range(steps):
        a0, a1 = o[0], o[1]  # PCPG reads the previous CPG output (one synapse, one step)
        cpg_step(o, w_self, w_cross)
        out[t, 0], out[t, 1] = o[0], o[1]
        out[t, 2] = pcpg_step(pc[0], a0, thr, partial)
        out[t, 3] = pcpg_step(pc[1], a1, thr, partial)


def simulate_cpg(steps: int, params: CpgParams | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Run the CPG and PCPG alone for ``steps`` control steps.

    Returns:
        (cpg, pcpg): two (steps, 2) arrays, the CPG outputs and the PCPG sawtooth outputs.
    """
    if steps < 1:
        raise ValueError(f"steps must be >= 1, got {steps!r}")
    p = params or CpgParams()
    o = np.full(2, p.start)
    pc = np.zeros((2, PCPG_FIELDS))
    out = np.empty((steps, 4))
    _run_cpg(o, pc, steps, p.w_self, p.w_cross + p.mi, p.pcpg_threshold, p.pcpg_first_partial, out)
    return out[:, :2].copy(), out[:, 2:].copy()


def period(signal: np.ndarray) -> float:
    """Mean period (in samples) of a periodic 1-D signal, from its upward zero crossings."""
    x = np.asarray(signal, dtype=float)
    up = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    if up.size < 2:
        raise ValueError("signal has fewer than two upward zero crossings")
    # Interpolate the crossing time within each step for sub-step precision.
    frac = -x[up] / (x[up + 1] - x[up])
    times = up + frac
    return float(np.mean(np.diff(times)))
