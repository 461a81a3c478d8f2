"""What every job runner shares: a finished job's result, the error of a worker that died, and the timed call a
worker makes.

The local process pool (:mod:`.local`), Ray (:mod:`.ray_backend`) and the sweep (:mod:`.sweep`) all import it; it
imports none of them.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TypeVar

T = TypeVar("T")
R = TypeVar("R")


class WorkerDiedError(RuntimeError):
    """The process running a job died (killed, segfault, ``os._exit``) before returning."""


@dataclass
class JobResult:
    """One finished job: ``value`` or ``error`` (the exception it raised, or a WorkerDiedError)."""

    index: int  # position of the job in the input
    value: object = None
    error: BaseException | None = None
    wall_time_s: float | None = None  # time the job took on its worker, s (None if the worker died)


def call_timed(fn: Callable[[T], R], item: T) -> tuple[R | None, BaseException | None, float]:
    """``fn(item)`` with the exception it raises caught: (value, error, wall time in s). Runs on the worker."""
    t0 = time.perf_counter()
    try:
        value: R | None = fn(item)
        error: Exception | None = None
    except Exception as e:
        value, error = None, e
    return value, error, time.perf_counter() - t0
