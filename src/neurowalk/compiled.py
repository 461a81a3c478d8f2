"""Compiled step functions: numba with an on-disk cache keyed on the whole package's source.

numba's own cache (``cache=True``) keys a compiled function on its own file only: a function that calls
a function of another file keeps running the old callee after that file is edited, silently. So every
compiled function of neurowalk is made by :func:`jit`, which puts numba's cache in a directory named
after the package version and a hash of all of the package's source files: any edit anywhere gives a
fresh directory, so nothing stale is ever loaded. The directory is under ``NUMBA_CACHE_DIR`` when that
is set, else under ``$XDG_CACHE_HOME/neurowalk/numba`` (``~/.cache/neurowalk/numba``); numba's setting
for other libraries is left as it was.

Parallel kernels (:func:`jit_parallel`) run on numba's ``workqueue`` threading layer unless
``NUMBA_THREADING_LAYER`` says otherwise. numba's default on PyPI's wheels is OpenMP, whose threads spin while they
wait for each other: with another process holding one of two cores (an RL learner beside the environments), two
OpenMP threads ran the vectorised environment at about 0.6 of one thread's rate, two ``workqueue`` threads at about
one thread's; on an idle machine OpenMP is the faster (``benchmarks/bench_threading.py``,
``docs/benchmarks/threading.json``).
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable
from functools import cache
from importlib import metadata
from pathlib import Path
from typing import Any, TypeVar

from numba import config, njit

F = TypeVar("F", bound=Callable[..., Any])
#: numba's threading layer for neurowalk's parallel kernels where ``NUMBA_THREADING_LAYER`` does not choose one.
THREADING_LAYER = "workqueue"
if "NUMBA_THREADING_LAYER" not in os.environ:
    config.THREADING_LAYER = THREADING_LAYER
PACKAGE = Path(__file__).resolve().parent


@cache
def source_key() -> str:
    """``VERSION-HASH``: the installed version and the SHA-256 (16 hex digits) of every ``.py`` file of the package."""
    h = hashlib.sha256()
    for path in sorted(PACKAGE.rglob("*.py")):
        h.update(path.relative_to(PACKAGE).as_posix().encode())
        h.update(path.read_bytes())
    try:
        version = metadata.version("neurowalk")
    except metadata.PackageNotFoundError:
        version = "unknown"
    return f"{version}-{h.hexdigest()[:16]}"


@cache
def cache_dir() -> Path:
    """Where neurowalk's compiled functions are cached (see the module doc)."""
    base = os.environ.get("NUMBA_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache"), "neurowalk", "numba"
    )
    return Path(base) / source_key()


def jit(fn: F) -> F:
    """``numba.njit(cache=True)`` with the cache in :func:`cache_dir` (numba reads the directory here, once)."""
    return _compiled(fn, parallel=False)


def jit_parallel(fn: F) -> F:
    """:func:`jit` with ``parallel=True``: ``numba.prange`` loops run on numba's threads (all cores by default)."""
    return _compiled(fn, parallel=True)


def _compiled(fn: F, parallel: bool) -> F:
    old = config.CACHE_DIR
    config.CACHE_DIR = str(cache_dir())
    try:
        return njit(cache=True, parallel=parallel)(fn)
    finally:
        config.CACHE_DIR = old
