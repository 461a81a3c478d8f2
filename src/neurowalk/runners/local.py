"""Run many jobs on a local process pool: results as they finish, a crashed worker costs only its own job.

:func:`run_unordered` is the engine (the sweep stores each result as it arrives); :func:`run_many` keeps the
simple form the experiments use (episode configs in, results in input order).
"""

from __future__ import annotations

import os
import signal
import sys
import time
from collections import deque
from collections.abc import Callable, Generator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from neurowalk.sim.episode import Episode, EpisodeConfig, run_episode


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


def run_unordered(fn: Callable[[Any], Any], items: Sequence[Any], *, workers: int = 2,
                  retries: int = 0) -> Generator[Done, None, None]:  # fmt: skip
    """Yield a :class:`Done` for every ``fn(item)`` as it finishes (in finishing order).

    Args:
        fn: a module-level function (pickled by reference into the workers).
        items: its arguments, one per job.
        workers: processes; 1 runs the jobs here, one after the other (so a crash would end this process).
        retries: how many more times a job whose worker died is run before it is reported (default 0: never).

    A job that raises gives a Done with that exception. A worker that dies (killed, segfault, ``os._exit``)
    breaks the pool: the job it was running is reported as :class:`WorkerDiedError` (or, with ``retries``, run
    again first); the other jobs the break cut short did not fail and run again on a fresh pool. Each worker
    notes the job it runs in a file named by its process id, which the pool's own SIGTERM to the survivors of a
    break removes, so the dead worker's job is the one whose note is left. Where no note is left (a worker
    that died between jobs, or by SIGTERM from outside), the cut-short jobs run one at a time to find it.
    """
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    if int(retries) != retries or retries < 0:
        raise ValueError(f"retries must be a whole number >= 0, got {retries!r}")
    if workers == 1:
        for i, item in enumerate(items):
            yield Done(i, *call_timed(fn, item))
        return
    import shutil
    import tempfile

    notes = Path(tempfile.mkdtemp(prefix="neurowalk-pool-"))
    deaths = dict.fromkeys(range(len(items)), 0)
    todo = deque(range(len(items)))
    try:
        while todo:
            lost, culprits = yield from _pool_pass(fn, items, todo, workers, notes)
            if lost and not culprits:  # nobody's note: one at a time, a job that breaks a pool alone is named
                alone = []
                for i in lost:
                    cut, _ = yield from _pool_pass(fn, items, deque([i]), 1, notes)
                    alone += cut
                lost = culprits = alone
            for i in lost:
                if i in culprits:
                    deaths[i] += 1
                    if deaths[i] > retries:
                        yield Done(i, error=WorkerDiedError(_died(deaths[i])))
                        continue
                if i not in todo:
                    todo.appendleft(i)
    finally:
        shutil.rmtree(notes, ignore_errors=True)


def _died(times: int) -> str:
    more = f" (the {times} times it ran)" if times > 1 else ""
    return f"the worker process died while running this job{more}: killed, a crash, or os._exit"


def _pool_pass(fn: Callable[[Any], Any], items: Sequence[Any], todo: deque[int], workers: int, notes: Path
               ) -> Generator[Done, None, tuple[list[int], list[int]]]:  # fmt: skip
    """Run jobs from ``todo`` on a new pool until it is empty or the pool breaks.

    Returns (the jobs a break cut short, those among them whose worker died). At most ``2 * workers`` jobs are
    in flight, so a break cuts short few and results stream back as they finish.
    """
    for stale in notes.iterdir():
        stale.unlink(missing_ok=True)
    pool = ProcessPoolExecutor(max_workers=workers, initializer=_worker_start, initargs=(os.getpid(), str(notes)))
    running: dict[Future, int] = {}
    lost: list[int] = []
    broken = False  # the pool broke (a submit can meet the break before any future reports it)
    try:
        while todo or running:
            while todo and len(running) < 2 * workers and not lost and not broken:
                i = todo.popleft()
                try:
                    running[pool.submit(_noted, fn, items[i], i)] = i
                except BrokenProcessPool:
                    todo.appendleft(i)  # not started: it goes to the next pool
                    broken = True
            if not running:
                break
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for fut in finished:
                i = running.pop(fut)
                try:
                    value, error, wall = fut.result()
                except BrokenProcessPool:
                    lost.append(i)
                    continue
                except Exception as e:  # e.g. a result that cannot be pickled
                    value, error, wall = None, e, None
                yield Done(i, value, error, wall)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
        todo.extendleft(reversed([i for i in running.values() if i not in lost]))  # on early exit keep the rest
    noted = {int(p.read_text() or -1) for p in notes.iterdir() if p.name.isdigit()}
    return sorted(lost), sorted(noted & set(lost))


_NOTES: Path | None = None  # a pool worker's folder of job notes (set by _worker_start)


def _worker_start(parent: int, notes: str) -> None:
    """Pool worker initializer: die with the driver; note jobs in ``notes``; a SIGTERM (the pool's, after a
    break) removes this worker's note, so that the job it was running is not blamed for the break."""
    global _NOTES
    die_with_parent(parent)
    _NOTES = Path(notes)

    def _terminated(signum: int, frame: object) -> None:
        (_NOTES / str(os.getpid())).unlink(missing_ok=True)  # type: ignore[operator]
        os._exit(128 + signum)

    signal.signal(signal.SIGTERM, _terminated)


def _noted(fn: Callable[[Any], Any], item: Any, index: int) -> tuple[Any, BaseException | None, float]:
    """:func:`call_timed` with this worker's note saying it runs job ``index`` (removed when it returns)."""
    note = _NOTES / str(os.getpid())  # type: ignore[operator]
    note.write_text(str(index))
    try:
        return call_timed(fn, item)
    finally:
        note.unlink(missing_ok=True)


def die_with_parent(parent: int) -> None:
    """Pool worker initializer: the worker dies with its driver, even a driver killed with SIGKILL.

    On Linux the kernel sends the worker SIGKILL when the driver exits (``prctl(PR_SET_PDEATHSIG)``); a driver that
    died before that was set (the worker's parent is no longer ``parent``) ends the worker at once.
    """
    if sys.platform.startswith("linux"):
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # 1 = PR_SET_PDEATHSIG
    if os.getppid() != parent:
        os._exit(1)


def summary_only(ep: Episode) -> dict[str, Any]:
    """Keep an episode's summary (the default of :func:`run_many`)."""
    return ep.summary


def _one(args: tuple[EpisodeConfig, Callable[[Episode], Any]]) -> Any:
    cfg, keep = args
    return keep(run_episode(cfg))


def run_many(configs: Sequence[EpisodeConfig], *, workers: int = 2, progress: bool = True,
             keep: Callable[[Episode], Any] = summary_only, desc: str = "runs") -> list[Any]:  # fmt: skip
    """Run every config; return ``keep(episode)`` of each, in order.

    Args:
        configs: the runs.
        workers: processes (1 runs them here, one after the other).
        progress: show a progress bar with rate and time left.
        keep: what to keep of each episode (a module-level function, so it can be pickled).

    Raises:
        the first error of a run as soon as it arrives (a worker that died: WorkerDiedError).
    """
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    from tqdm import tqdm

    jobs = [(c, keep) for c in configs]
    out: list[Any] = [None] * len(jobs)
    warp = [i for i, c in enumerate(configs) if c.engine == "warp"]
    if warp:  # as the worlds of MuJoCo Warp models, here (the device is this process's)
        from neurowalk.runners.sweep import warp_groups
        from neurowalk.sim.warp_engine import run_warp

        for chunk, device in warp_groups([(configs[i].steps, configs[i].control_hz) for i in warp]):
            eps = run_warp([configs[warp[j]] for j in chunk], device=device, progress=progress)
            for j, ep in zip(chunk, eps, strict=True):
                out[warp[j]] = keep(ep)
    rest = [i for i, c in enumerate(configs) if c.engine != "warp"]
    jobs = [jobs[i] for i in rest]
    if not jobs:
        return out
    with tqdm(total=len(jobs), unit="run", desc=desc, disable=not progress, mininterval=0.5) as bar:
        results = run_unordered(_one, jobs, workers=1 if len(jobs) <= 1 else workers)
        try:
            for d in results:
                if d.error is not None:
                    raise d.error
                out[rest[d.index]] = d.value
                bar.update(1)
        finally:
            results.close()  # stops the pool at once on an error
    return out
