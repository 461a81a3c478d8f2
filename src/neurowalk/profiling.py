"""Where a command's time goes: seconds per part of the work, summed over its process and the workers it forks.

The parts (:data:`PARTS`):

* ``physics``: MuJoCo's physics steps (``mj_step``) of the CPU loop, with their count (the physics steps per second);
* ``control``: the rest of the control loop: sensors and their noise, the networks, the rows recorded;
* ``summary``: a run's numbers made from its rows (coverage, wedged periods, ...);
* ``store``: results written into the result stores;
* ``drawing``: the figure's picture, drawn and saved;
* ``video``: rendered frames and videos.

What is left of a command's wall time is start-up (imports, compiling), building models and arenas, waiting on
workers, and the surrogate's loop. Every process adds its seconds with :func:`add` or :func:`part`; where the
environment variable :data:`ENV` names a folder, each process (the command's and every worker forked from it, which
starts from zero) writes its own sums at its exit to ``FOLDER/profile-PID.json``, and :func:`read_profile` adds
them up (``neurowalk reproduce`` does, per figure, into its records).
"""

from __future__ import annotations

import atexit
import contextlib
import json
import os
import time
from collections.abc import Iterator
from multiprocessing import util
from pathlib import Path
from typing import Any

#: The environment variable naming the folder the processes write their sums into (unset: nothing is written).
ENV = "NEUROWALK_PROFILE"
#: The parts, in the order a profile lists them.
PARTS = ("physics", "control", "summary", "store", "drawing", "video")

_seconds: dict[str, float] = {}
_counts: dict[str, int] = {}


def add(name: str, seconds: float, count: int = 0) -> None:
    """Add ``seconds`` (and ``count`` events, e.g. physics steps) to part ``name``."""
    _seconds[name] = _seconds.get(name, 0.0) + seconds
    if count:
        _counts[name] = _counts.get(name, 0) + count


@contextlib.contextmanager
def part(name: str) -> Iterator[None]:
    """Count the block's wall time to part ``name``."""
    t0 = time.perf_counter()
    try:
        yield
    finally:
        add(name, time.perf_counter() - t0)


def totals() -> dict[str, Any]:
    """This process's sums so far: ``{"seconds": {part: s}, "counts": {part: n}}``."""
    return {"seconds": dict(_seconds), "counts": dict(_counts)}


def _write() -> None:
    """Write this process's sums to ``$NEUROWALK_PROFILE/profile-PID.json`` (nothing where unset or nothing spent)."""
    folder = os.environ.get(ENV)
    if not folder or not _seconds:
        return
    path = Path(folder) / f"profile-{os.getpid()}.json"
    with contextlib.suppress(OSError):  # a profile is a report: a folder that went away loses it, not the run
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps(totals()), encoding="utf-8")
        tmp.replace(path)


class _Forked:
    """A handle for multiprocessing's after-fork hook (it keeps a weak reference)."""


def _in_child(_: _Forked) -> None:
    """A forked worker starts from zero and writes its own sums when it ends (multiprocessing's finalizers run
    where ``atexit`` does not)."""
    _seconds.clear()
    _counts.clear()
    util.Finalize(None, _write, exitpriority=0)


_HANDLE = _Forked()
util.register_after_fork(_HANDLE, _in_child)
atexit.register(_write)


def read_profile(folder: Path, wall_s: float | None = None) -> dict[str, Any]:
    """The sums of every ``profile-*.json`` in ``folder``: seconds per part (CPU seconds over all processes: with
    workers they can add up to more than the wall time), the physics steps and their rate per second of physics,
    and, given the command's ``wall_s``, the parts' share of the wall time times the processes' count."""
    seconds: dict[str, float] = {}
    counts: dict[str, int] = {}
    files = sorted(Path(folder).glob("profile-*.json"))
    for path in files:
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        for k, v in data.get("seconds", {}).items():
            seconds[k] = seconds.get(k, 0.0) + float(v)
        for k, v in data.get("counts", {}).items():
            counts[k] = counts.get(k, 0) + int(v)
    ordered = {k: round(seconds[k], 2) for k in (*PARTS, *sorted(set(seconds) - set(PARTS))) if k in seconds}
    steps = counts.get("physics", 0)
    out: dict[str, Any] = {
        "processes": len(files),
        "seconds": ordered,
        "physics_steps": steps,
        "physics_steps_per_s": round(steps / seconds["physics"]) if seconds.get("physics") else None,
    }
    if wall_s:
        out["wall_time_s"] = wall_s
    return out
