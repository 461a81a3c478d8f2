"""What every job runner shares: a finished job's result, the error of a worker that died, the timed call a worker
makes, and the grouping of MuJoCo Warp runs into the worlds of one model.

The local process pool (:mod:`.local`), Ray (:mod:`.ray_backend`) and the sweep (:mod:`.sweep`) all import it; it
imports none of them.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any


class WorkerDiedError(RuntimeError):
    """The process running a job died (killed, segfault, ``os._exit``) before returning."""


@dataclass
class Done:
    """One finished job: ``value`` or ``error`` (the exception it raised, or a WorkerDiedError)."""

    index: int  # position of the job in the input
    value: Any = None
    error: BaseException | None = None
    wall_time_s: float | None = None  # time the job took on its worker, s (None if the worker died)


def call_timed(fn: Callable[[Any], Any], item: Any) -> tuple[Any, BaseException | None, float]:
    """``fn(item)`` with the exception it raises caught: (value, error, wall time in s). Runs on the worker."""
    t0 = time.perf_counter()
    try:
        value, error = fn(item), None
    except Exception as e:
        value, error = None, e
    return value, error, time.perf_counter() - t0


def warp_groups(keys: list[tuple[Any, Any]], worlds: int | None = None) -> Iterator[tuple[list[int], str]]:
    """Indices of runs that can share one MuJoCo Warp model (same ``keys[i]``: steps and control rate), at most
    ``worlds`` at a time (default 4096 on a GPU, 16 on the CPU device), with the device to run them on."""
    from neurowalk.sim.warp_engine import resolve_device

    device = resolve_device()
    worlds = worlds or (4096 if device == "cuda" else 16)
    groups: dict[tuple[Any, Any], list[int]] = {}
    for i, key in enumerate(keys):
        groups.setdefault(key, []).append(i)
    for group in groups.values():
        for c in range(0, len(group), worlds):
            yield group[c : c + worlds], device
