"""A figure's runs kept in resumable result stores in its output folder.

:func:`run_store` runs specs through a store (each run stored as it finishes, so an interrupted figure keeps its
finished runs and the same call again runs only the others); :func:`store_folder` is the folder of a figure's stores;
:func:`as_lists` is a run's result as a store keeps it.

:func:`shared_stores` puts every store of the figures run inside it into one folder shared by many figures (``neurowalk
figure --shared-runs DIR``; ``neurowalk reproduce`` shares one across its figures): one store per function that
runs a spec, so a run one figure made is taken by another that asks for the same config and the same kept result
(the same config gives the same result bit for bit), not run again.
"""

from __future__ import annotations

import contextlib
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk.runners.specs import run_spec, spec_key
from neurowalk.runners.stopping import deferred
from neurowalk.runners.store import ResultStore
from neurowalk.runners.sweep import run_sweep
from neurowalk.sim.engine import EngineOptions

_SHARED: list[Path] = []  # the folder of shared stores in force (shared_stores), innermost last


@contextlib.contextmanager
def shared_stores(folder: Path) -> Iterator[Path]:
    """Inside the block, :func:`run_store` keeps and takes runs in ``folder``'s stores, one per run function (named
    after it: ``neurowalk.runners.specs.run_spec.sqlite``), instead of the figure's own."""
    folder = Path(folder)
    _SHARED.append(folder)
    try:
        yield folder
    finally:
        _SHARED.pop()


def store_path(folder: Path, name: str, fn: Any) -> Path:
    """Where :func:`run_store` keeps the runs of ``fn`` (None: ``run_spec``): ``folder/name``, or inside
    :func:`shared_stores` the shared folder's store of that function."""
    if not _SHARED:
        return Path(folder) / name
    f = fn if fn is not None else run_spec
    return _SHARED[-1] / f"{f.__module__}.{f.__qualname__}.sqlite"


def store_files(folder: Path) -> list[Path]:
    """The result stores :func:`run_store` keeps a figure's runs in: ``folder``'s, or inside :func:`shared_stores`
    the shared folder's (which hold other figures' runs too)."""
    return sorted((_SHARED[-1] if _SHARED else Path(folder)).glob("*.sqlite"))


def run_store(
    specs: list[dict[str, Any]],
    folder: Path,
    workers: int,
    fn: Any = None,
    name: str = "results.sqlite",
    options: EngineOptions | None = None,
    backend: str = "local",
    address: str | None = None,
    desc: str = "sweep",
) -> tuple[dict[str, dict[str, Any]], Any]:
    """Run ``specs`` through the resumable store ``folder/name``; return (results by spec key, report).

    ``fn``: what runs one spec (default :func:`~neurowalk.runners.specs.run_spec`; a module-level function).
    Each run is stored as it finishes: an interrupted figure (KeyboardInterrupt, raised here once the store is
    closed) keeps its finished runs, and the same call again runs only the others. ``options``: how the engines run
    (e.g. MuJoCo Warp's device); ``backend``, ``address``: a process pool (``local``) or Ray (and the cluster to
    join); ``desc``: the progress bar's label.
    """
    path = store_path(folder, name, fn)
    path.parent.mkdir(parents=True, exist_ok=True)
    with deferred():  # opened whole (its lock, its tables), or not at all
        store = ResultStore(path)
    with store:
        report = run_sweep(
            specs,
            store,
            workers=workers,
            options=options,
            backend=backend,
            address=address,
            desc=desc,
            **({"fn": fn} if fn is not None else {}),
        )
        results = store.results()
    if report.interrupted:
        raise KeyboardInterrupt
    keys = [spec_key(s) for s in specs]  # once: a key costs a config's checks
    missing = [k for k in keys if k not in results]
    if missing:
        raise RuntimeError(f"{len(missing)} runs failed (see {path}); rerun to retry them")
    return {k: results[k] for k in keys}, report


@contextlib.contextmanager
def store_folder(out: Path | None) -> Iterator[Path]:
    """The folder of a figure's stores: ``out``, or (a figure run from Python without one) a temporary folder,
    removed afterwards."""
    if out is not None:
        yield Path(out)
        return
    with tempfile.TemporaryDirectory(prefix="neurowalk-") as tmp:
        yield Path(tmp)


def as_lists(d: dict[str, Any]) -> dict[str, Any]:
    """``d`` with its numpy arrays as lists (a run's result as a store keeps it: JSON)."""
    return {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in d.items()}
