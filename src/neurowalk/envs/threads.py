"""How many of numba's threads a parallel kernel runs on: the faster of one and all, measured while it runs.

Two threads split a call's work in two, and the call ends when both halves are done. Where another process holds
one of the cores (an RL learner beside the environments, a second job), the thread that shares a core with it
finishes late, and the call can take longer than on one thread alone; on an idle machine two threads are the
faster. :class:`ThreadChooser` runs each call on the count that has been the faster: it times calls in blocks,
runs every ``probe``-th block on the other count, and keeps a moving average of the time per call of each. What a
kernel computes does not depend on how many threads run it, so the choice changes no result, only the speed.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numba

__all__ = ["ThreadChooser"]


class ThreadChooser:
    """Calls a parallel kernel on 1 or ``most`` numba threads, whichever has been the faster per call.

    Args:
        most: the larger count (default: numba's thread count where the chooser is made, ``numba.get_num_threads()``).
        block: calls timed together (one timing of a call of about a millisecond is mostly noise).
        probe: every ``probe``-th block runs on the count not chosen, so a change of load is seen (0: never; the
            kernel runs on ``most`` threads, as a benchmark of a fixed count needs).
        smoothing: weight of the newest block in each count's moving average of seconds per call.
    """

    def __init__(self, most: int | None = None, *, block: int = 16, probe: int = 32, smoothing: float = 0.3) -> None:
        self.most = int(most if most is not None else numba.get_num_threads())
        self.block, self.probe, self.smoothing = block, probe, smoothing
        self.chosen = self.most
        self.per_call: dict[int, float] = {}  # threads -> moving average of seconds per call
        self._calls = 0  # calls in the current block
        self._blocks = 0
        self._threads = self.most  # the count of the current block
        self._spent = 0.0  # seconds of the current block so far

    def __call__(self, kernel: Callable[..., Any], *args: Any) -> Any:
        """``kernel(*args)`` on the current block's thread count (numba's setting is put back after)."""
        old = numba.get_num_threads()
        numba.set_num_threads(self._threads)
        t0 = time.perf_counter()
        try:
            return kernel(*args)
        finally:
            self.record(time.perf_counter() - t0)
            numba.set_num_threads(old)

    def record(self, seconds: float) -> None:
        """Count one call of ``seconds`` towards the current block; at its end update the averages and choose."""
        if self.most <= 1:
            return
        self._spent += seconds
        self._calls += 1
        if self._calls < self.block:
            return
        n, per = self._threads, self._spent / self._calls
        old = self.per_call.get(n)
        self.per_call[n] = per if old is None else (1 - self.smoothing) * old + self.smoothing * per
        if len(self.per_call) == 2:
            self.chosen = min(self.per_call, key=self.per_call.__getitem__)
        self._blocks += 1
        self._calls, self._spent = 0, 0.0
        other = 1 if self.chosen == self.most else self.most
        # the other count's first block comes second, so that both are measured early
        probing = self.probe > 0 and (self._blocks == 1 or self._blocks % self.probe == 0)
        self._threads = other if probing else self.chosen
