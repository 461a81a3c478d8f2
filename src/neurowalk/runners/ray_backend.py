"""Run many jobs on Ray: a local Ray instance, or a cluster joined by address (``--backend ray --address ...``).

``ray`` is imported only here, only when this backend is chosen (it is the optional extra ``neurowalk[ray]``).
Each job is a Ray task of one CPU; the driver collects results with ``ray.wait`` as they finish, so the sweep
stores them as they arrive. A job that raises comes back as an error; a task whose worker died (crash,
``os._exit``, lost node) runs again up to ``retries`` more times (Ray's ``max_retries``), then is reported as
:class:`~neurowalk.runners.jobs.WorkerDiedError`. Ray's own log (its workers' output, the raylet's messages) stays
out of the terminal unless ``NEUROWALK_RAY_LOG=1`` asks for it.
"""

from __future__ import annotations

import logging
import os
import re
import sys
from collections.abc import Callable, Generator, Sequence
from typing import Any

from neurowalk.runners.jobs import JobResult, T, WorkerDiedError, call_timed

#: The environment variable that shows Ray's own log in the terminal ("1"); unset, only Ray's errors are shown.
LOG_ENV = "NEUROWALK_RAY_LOG"
INSTALL_HINT = "the ray backend needs `pip install -e '.[ray]'` in neurowalk's folder"


class RayMissingError(ImportError):
    """Ray is not installed."""


class RayStartError(RuntimeError):
    """Ray could not be started, or the cluster could not be joined."""


def import_ray() -> Any:
    """``import ray``, or raise :class:`RayMissingError` with the install hint if ray itself is missing.

    Other import errors (a broken ray install) propagate unchanged.
    """
    try:
        import ray
    except ModuleNotFoundError as e:
        if e.name != "ray":
            raise
        raise RayMissingError(INSTALL_HINT) from None
    return ray


def start(*, workers: int = 2, address: str | None = None) -> bool:
    """Connect to Ray unless already connected; return True if this call started it (then :func:`stop` it).

    With ``address`` join that cluster (``ray.init(address=...)``), else start a local instance of ``workers``
    CPUs without dashboard.
    """
    ray = import_ray()
    if ray.is_initialized():
        return False
    shown = os.environ.get(LOG_ENV, "").strip() == "1"  # Ray's own log in the terminal only where asked for
    quiet = {"log_to_driver": shown, "logging_level": logging.INFO if shown else logging.ERROR}
    if not shown:
        _one_line_errors()
    try:
        if address:
            ray.init(address=address, **quiet)
        else:
            ray.init(num_cpus=workers, include_dashboard=False, **quiet)
    except (ConnectionError, ValueError, RuntimeError, TimeoutError) as e:
        where = f"join the Ray cluster at {address!r}" if address else "start a local Ray instance"
        raise RayStartError(f"cannot {where}: {str(e).strip().splitlines()[0] if str(e).strip() else e!r}") from None
    return True


def _one_line_errors() -> None:
    """The errors Ray's cluster reports to the driver (a node's raylet gone: the last lines of its log, some 40) in
    one line each, on stderr: ``neurowalk: Ray: Raylet is terminated. ...``. Ray's driver prints them whole on
    stdout from a thread of its own, through ``ray._private.worker.print_to_stdstream`` (Ray 2.40 to 2.60; where a
    Ray has none, its own printing stays)."""
    import importlib

    worker = importlib.import_module("ray._private.worker")
    whole = getattr(worker, "print_to_stdstream", None)
    if whole is None or getattr(whole, "one_line", False):
        return

    said: set[str] = set()

    def one_line(data: dict[str, Any], ignore_prefix: bool) -> None:
        if data.get("pid") != "raylet":  # a worker's own output (shown only with the log): as Ray prints it
            whole(data, ignore_prefix)
            return
        first = next((t.strip() for line in data.get("lines", []) for t in str(line).splitlines() if t.strip()), "")
        line = " ".join(re.split(r"(?<=\.) ", first)[:2])[:200]  # its first two sentences
        if line not in said:  # each once (a node's death comes from more than one of Ray's parts)
            said.add(line)
            print(f"neurowalk: Ray: {line}", file=sys.stderr, flush=True)

    one_line.one_line = True  # type: ignore[attr-defined]
    worker.print_to_stdstream = one_line  # type: ignore[attr-defined]


def stop() -> None:
    """Shut Ray down (only call it if :func:`start` returned True)."""
    import_ray().shutdown()


def run_unordered(
    fn: Callable[[T], object], items: Sequence[T], *, workers: int = 2, address: str | None = None, retries: int = 0
) -> Generator[JobResult, None, None]:
    """Yield a :class:`JobResult` for every ``fn(item)`` as it finishes, computed as Ray tasks.

    Args:
        fn: a module-level function, importable on the workers.
        items: its arguments, one per job.
        workers: CPUs of the local instance (ignored when joining a cluster or when Ray is already running).
        address: the cluster to join (e.g. ``"auto"`` or ``"10.0.0.1:6379"``); None starts a local instance.
        retries: how many more times Ray runs a job whose worker died before it is reported (``max_retries``).

    At most twice the cluster's CPUs are in flight, so results stream back and an interrupt cancels few jobs.
    """
    ray = import_ray()
    started = start(workers=workers, address=address)
    task = ray.remote(num_cpus=1, max_retries=retries)(call_timed)
    window = 2 * max(1, int(ray.cluster_resources().get("CPU", workers)))
    fn_ref = ray.put(fn)
    pending: dict[Any, int] = {}
    next_i = 0
    try:
        while next_i < len(items) or pending:
            while next_i < len(items) and len(pending) < window:
                pending[task.remote(fn_ref, items[next_i])] = next_i
                next_i += 1
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                yield _collect(ray, ref, pending.pop(ref))
    finally:
        for ref in pending:
            ray.cancel(ref, force=True)
        if started:
            stop()


def _collect(ray: Any, ref: Any, i: int) -> JobResult:
    """The JobResult of a finished task (its value, its caught exception, or the Ray error that ended it)."""
    try:
        value, error, wall = ray.get(ref)
    except ray.exceptions.RayTaskError as e:  # raised outside fn, e.g. fn could not be unpickled on the worker
        cause = getattr(e, "cause", None)
        return JobResult(i, error=cause if isinstance(cause, Exception) else RuntimeError(_first_line(e)))
    except ray.exceptions.RayError as e:  # WorkerCrashedError, NodeDiedError, ObjectLostError, OutOfMemoryError...
        return JobResult(i, error=WorkerDiedError(f"the Ray worker died while running this job ({type(e).__name__})"))
    return JobResult(i, value, error, wall)


def _first_line(e: BaseException) -> str:
    text = str(e).strip()
    return text.splitlines()[0] if text else type(e).__name__
