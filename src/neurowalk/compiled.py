"""Compiled step functions: numba with an on-disk cache keyed on the code that computes runs.

numba's own cache (``cache=True``) keys a compiled function on its own file only: a function that calls
a function of another file keeps running the old callee after that file is edited, silently. So every
compiled function of neurowalk is made by :func:`jit`, which puts numba's cache in a directory named
after the package version and the code's fingerprint (:func:`neurowalk.fingerprint.code`, the same code a result
store keys its runs by; a user's file that compiles its own function with :func:`jit` is part of that function's
key): any edit of that code gives a fresh directory, so nothing stale is ever loaded. The directory is under
``NUMBA_CACHE_DIR`` when that is set, else under ``$XDG_CACHE_HOME/neurowalk/numba`` (``~/.cache/neurowalk/numba``);
numba's setting for other libraries is left as it was.

Parallel kernels (:func:`jit_parallel`) run on numba's ``workqueue`` threading layer unless
``NUMBA_THREADING_LAYER`` says otherwise; the layer is set when the first of them is made (importing this module
changes no numba setting: a process that makes no parallel kernel of neurowalk's keeps numba's own choice).
numba's default on PyPI's wheels is OpenMP, whose threads spin while they wait for each other: with another
process holding one of two cores (an RL learner beside the environments), two OpenMP threads ran the vectorised
environment at about 0.6 of one thread's rate, two ``workqueue`` threads at about one thread's; on an idle machine
OpenMP is the faster (``benchmarks/bench_threading.py``, ``docs/benchmarks/threading.json``).

numba compiles a kernel when it is first called with its argument types, or loads it from the cache: a command
compiles only the kernels its work calls. The first compile of a process is announced in one line on stderr
(:func:`neurowalk.progress.compiling`), from numba's own compile event, which fires only where no cached copy was
found: never on a warm cache.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from functools import cache
from importlib import metadata
from pathlib import Path
from typing import Any, TypeVar

from numba import config, njit
from numba.core import event

from neurowalk import fingerprint, progress

F = TypeVar("F", bound=Callable[..., Any])
#: numba's threading layer for neurowalk's parallel kernels where ``NUMBA_THREADING_LAYER`` does not choose one.
THREADING_LAYER = "workqueue"


@cache
def source_key(files: tuple[Path, ...] = ()) -> str:
    """``VERSION-CODE``: the installed version and :func:`neurowalk.fingerprint.code` of the package with the user's
    ``files``."""
    try:
        version = metadata.version("neurowalk")
    except metadata.PackageNotFoundError:
        version = "unknown"
    return f"{version}-{fingerprint.code(files)}"


@cache
def cache_dir(files: tuple[Path, ...] = ()) -> Path:
    """Where neurowalk's compiled functions are cached (see the module doc); ``files``: the user's files of a
    function compiled outside the package."""
    base = os.environ.get("NUMBA_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache"), "neurowalk", "numba"
    )
    return Path(base) / source_key(files)


def jit(fn: F) -> F:
    """``numba.njit(cache=True)`` with the cache in :func:`cache_dir` (numba reads the directory here, once)."""
    return _compiled(fn, parallel=False)


def jit_parallel(fn: F) -> F:
    """:func:`jit` with ``parallel=True``: ``numba.prange`` loops run on numba's threads (all cores by default), on
    :data:`THREADING_LAYER` unless ``NUMBA_THREADING_LAYER`` chooses one."""
    if "NUMBA_THREADING_LAYER" not in os.environ:
        config.THREADING_LAYER = THREADING_LAYER
    return _compiled(fn, parallel=True)


class _CompileNote(event.Listener):  # type: ignore[misc]
    """numba's ``numba:compile`` event (a compile, after no cached copy was found): the compile note of a kernel of
    neurowalk's."""

    def on_start(self, ev: event.Event) -> None:
        dispatcher = ev.data.get("dispatcher") if isinstance(ev.data, dict) else None
        module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
        if module.split(".")[0] == __name__.split(".")[0]:
            progress.compiling(cache_dir())

    def on_end(self, ev: event.Event) -> None:
        pass


@cache
def _listen() -> None:
    """Listen to numba's compile events (once, when the first kernel of neurowalk's is made)."""
    event.register("numba:compile", _CompileNote())


def _compiled(fn: F, parallel: bool) -> F:
    _listen()
    old = config.CACHE_DIR
    config.CACHE_DIR = str(cache_dir(tuple(fingerprint.user_files(fn))))
    try:
        return njit(cache=True, parallel=parallel)(fn)
    finally:
        config.CACHE_DIR = old
