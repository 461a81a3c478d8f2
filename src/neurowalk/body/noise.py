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

import numpy as np

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
