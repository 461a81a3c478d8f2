"""Coloured sensor noise of the original simulator (LPZRobots ``ColorUniformNoise``).

Per sensor and control step: n ← n + sqrt(tau)·U(-1, 1)·strength - tau·n, with strength 0.02 and
tau 0.05 (stationary standard deviation about 0.008), drawn from the run's Generator.

The uniform numbers are drawn :data:`BLOCK` control steps at a time: ``uniform(-1, 1, (BLOCK, n))`` gives the same
numbers, in the same order, as ``BLOCK`` draws of ``n`` (numpy's Generator fills arrays element by element), so the
noise is bit for bit that of one draw per step, at a fraction of the cost. The Generator is the body's own (spawned
for the noise alone), so drawing ahead changes nothing else; a pickled body carries its block.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence

import numpy as np

from neurowalk.compiled import jit

BLOCK = 256  # control steps of uniform numbers drawn at once


class ColoredNoise:
    """Low-pass filtered uniform noise for ``n`` channels (dimensionless, in sensor units)."""

    def __init__(self, n: int, strength: float = 0.02, tau: float = 0.05) -> None:
        if strength < 0 or not 0 < tau <= 1:
            raise ValueError(f"noise needs strength >= 0 and 0 < tau <= 1, got {strength}, {tau}")
        self.n, self.strength, self.tau = n, strength, tau
        self.value = np.zeros(n)
        self._rng = np.random.default_rng(0)
        self._gain = math.sqrt(tau) * strength
        self._block = np.empty((0, n))  # uniform numbers drawn ahead (BLOCK, n), and the next row to use
        self._next = 0

    def reset(self, rng: np.random.Generator) -> None:
        """Zero state; draws from ``rng`` from now on."""
        self._rng = rng
        self.value[:] = 0.0
        self._block = np.empty((0, self.n))
        self._next = 0

    def step(self) -> np.ndarray:
        """Advance one control step; returns the current noise (n,) (the internal buffer)."""
        if self.strength > 0:
            if self._next == len(self._block):
                self._block = self._rng.uniform(-1.0, 1.0, (BLOCK, self.n))
                self._next = 0
            v = self.value
            v += self._gain * self._block[self._next] - self.tau * v
            self._next += 1
        return self.value


class ColoredNoiseBatch:
    """The :class:`ColoredNoise` sources of n lock-step worlds, stepped together: one array operation a control
    step for all of them, the same numbers, bit for bit, as each source's own :meth:`~ColoredNoise.step`.

    Each world draws its uniform numbers from its own source's Generator, :data:`BLOCK` steps at a time, as the
    source does (a Python loop over the due worlds once every :data:`BLOCK` of their steps); the filter step is the
    source's arithmetic, element by element, in one compiled call. A world of strength 0 stays at 0 and draws nothing,
    as its source does. A world reset on its own goes on from its own block's first row.

    Args:
        sources: one per world, all with the same number of channels.

    Attributes:
        value: (n, channels) the current noise of every world (updated in place by :meth:`step`).
        draw_s: seconds spent drawing blocks so far; blocks: blocks drawn (each :data:`BLOCK` steps of all worlds).
    """

    def __init__(self, sources: list[ColoredNoise]) -> None:
        channels = {s.n for s in sources}
        if len(channels) > 1:
            raise ValueError(f"the worlds' noise sources need the same channels, got {sorted(channels)}")
        self.sources = sources
        self.channels = channels.pop() if channels else 0
        self.on = np.array([s.strength > 0 for s in sources], dtype=bool)
        self._gain = np.array([[s._gain] for s in sources]) if sources else np.zeros((0, 1))
        self._tau = np.array([[s.tau] for s in sources]) if sources else np.zeros((0, 1))
        self.value = np.zeros((len(sources), self.channels))
        self._block = np.zeros((len(sources), BLOCK, self.channels))
        self._next = np.full(len(sources), BLOCK)  # each world's next row of its block (BLOCK: draw a new one)
        self._due = True  # a world needs a new block before its next step
        self.draw_s, self.blocks = 0.0, 0

    def reset(self, rngs: Sequence[np.random.Generator], ids: Sequence[int] | np.ndarray | None = None) -> None:
        """Every world's source (or those of worlds ``ids``) reset with its Generator (:meth:`ColoredNoise.reset`);
        zero state. A world reset on its own (a Gymnasium copy's new episode) draws its blocks from then on, as its
        source would: bit for bit its own run's noise whatever the other worlds do."""
        which = range(len(self.sources)) if ids is None else [int(i) for i in ids]
        for i, rng in zip(which, rngs, strict=True):
            self.sources[i].reset(rng)
            self.value[i] = 0.0
            self._next[i] = BLOCK
        self._due = True

    def step(self) -> np.ndarray:
        """Advance every world one control step; returns :attr:`value`."""
        if self._due:  # a world has used its block: its next one from its Generator
            nxt = self._next
            t = time.perf_counter()
            for i in np.flatnonzero((nxt == BLOCK) & self.on):
                self._block[i] = self.sources[i]._rng.uniform(-1.0, 1.0, (BLOCK, self.channels))
            nxt[nxt == BLOCK] = 0
            self.draw_s += time.perf_counter() - t
            self.blocks += 1
        self._due = _filter_step(self._block, self._next, self._gain, self._tau, self.on, self.value)
        return self.value


@jit
def _filter_step(
    block: np.ndarray, nxt: np.ndarray, gain: np.ndarray, tau: np.ndarray, on: np.ndarray, value: np.ndarray
) -> bool:
    """One step of every world's filter (``value`` (n, channels) += gain * u - tau * value, u the next row of its
    ``block`` (n, BLOCK, channels); :class:`ColoredNoise`'s arithmetic, element by element); returns whether a world
    has used the last row of its block."""
    due = False
    for i in range(value.shape[0]):
        row = nxt[i]
        if on[i]:
            g, t = gain[i, 0], tau[i, 0]
            for c in range(value.shape[1]):
                v = value[i, c]
                value[i, c] = v + (g * block[i, row, c] - t * v)
        nxt[i] = row + 1
        if row + 1 == BLOCK:
            due = True
    return due
