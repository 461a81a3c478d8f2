"""Run many jobs on a local process pool: results as they finish, a crashed worker costs only its own job.

:func:`run_unordered` is the engine of the one runner (:func:`~neurowalk.runners.sweep.run_sweep` stores each result
as it arrives; every batch of episodes goes through it).

The pool is this module's own: one pipe to each worker process, which runs one job at a time, so the driver knows
which job each worker runs. A worker that dies (killed, segfault, ``os._exit``) costs only its own job, and the
others go on; an idle one that dies costs nothing. Workers ignore SIGINT and SIGTERM (a terminal's Ctrl-C reaches
the whole process group): the driver decides. When the driver stops early (an error, Ctrl-C, the consumer closing the
generator) it kills its workers and reaps them before it goes on, so that no worker outlives the stop and no
interpreter exit waits on one; a driver killed outright takes its workers with it (``PR_SET_PDEATHSIG``). A worker
that compiles the kernels says so down its pipe, and the driver writes the note (:mod:`neurowalk.progress`), once.
"""

from __future__ import annotations

import contextlib
import ctypes
import multiprocessing
import os
import signal
import sys
from collections import deque
from collections.abc import Callable, Generator, Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection
from multiprocessing.connection import wait as mp_wait
from multiprocessing.process import BaseProcess
from multiprocessing.reduction import ForkingPickler

from neurowalk.compiled import cache_dir
from neurowalk.progress import compiling, forward_notes
from neurowalk.runners.jobs import JobResult, T, WorkerDiedError, call_timed
from neurowalk.runners.stopping import deferred, stop_requested

#: What a worker sends down its pipe as it starts compiling the kernels (a job's result is a pickle: never this).
COMPILING = b"compiling"


def run_unordered(
    fn: Callable[[T], object], items: Sequence[T], *, workers: int = 2, retries: int = 0
) -> Generator[JobResult, None, None]:
    """Yield a :class:`JobResult` for every ``fn(item)`` as it finishes (in finishing order).

    Args:
        fn: a module-level function (pickled by reference into the workers).
        items: its arguments, one per job.
        workers: processes; 1 runs the jobs here, one after the other (so a crash would end this process).
        retries: how many more times a job whose worker died is run before it is reported (default 0: never).

    A job that raises gives a JobResult with that exception (so does a job whose item or result cannot be pickled).
    A job whose worker dies gives a :class:`WorkerDiedError` (or, with ``retries``, runs again first, on a fresh
    worker); the other workers go on.
    """
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    if int(retries) != retries or retries < 0:
        raise ValueError(f"retries must be a whole number >= 0, got {retries!r}")
    if workers == 1:
        for i, item in enumerate(items):
            if stop_requested():
                raise KeyboardInterrupt
            yield JobResult(i, *call_timed(fn, item))
        return
    deaths = dict.fromkeys(range(len(items)), 0)
    todo = deque(range(len(items)))
    pool = _Pool(min(workers, len(items)))
    finished = False
    try:
        while todo or pool.busy():
            while todo and pool.has_room():
                i = todo.popleft()
                try:
                    job = ForkingPickler.dumps((fn, items[i], i))
                except Exception as e:  # an item (or fn) that cannot be pickled: that job's error
                    yield JobResult(i, error=e)
                    continue
                if not pool.submit(job, i):
                    todo.appendleft(i)  # its worker had died before it got the job: not the job's fault
            if stop_requested():  # a Ctrl-C that some library swallowed
                raise KeyboardInterrupt
            if not pool.busy():
                continue
            for i, done in pool.wait():
                if done is not None:
                    yield done
                    continue
                deaths[i] += 1
                if deaths[i] > retries:
                    yield JobResult(i, error=WorkerDiedError(_died(deaths[i])))
                else:
                    todo.appendleft(i)
        finished = True
    finally:
        with deferred():
            pool.close(finished)


def _died(times: int) -> str:
    more = f" (the {times} times it ran)" if times > 1 else ""
    return f"the worker process died while running this job{more}: killed, a crash, or os._exit"


@dataclass
class _Worker:
    proc: BaseProcess
    conn: Connection  # the driver's end of the worker's pipe
    job: int | None = None  # the job it runs (None: idle)


class _Pool:
    """Up to ``size`` worker processes, started as jobs need them, one job each at a time."""

    def __init__(self, size: int) -> None:
        self.size = size
        self.ctx = multiprocessing.get_context()
        self.workers: list[_Worker] = []

    def busy(self) -> bool:
        return any(w.job is not None for w in self.workers)

    def has_room(self) -> bool:
        return len(self.workers) < self.size or any(w.job is None for w in self.workers)

    def submit(self, job: bytes | memoryview, index: int) -> bool:
        """Send a pickled job to an idle worker (started if need be); False if that worker had died."""
        w = next((w for w in self.workers if w.job is None), None)
        with deferred():  # a signal must not leave a started worker out of the list
            if w is None:
                conn, child = self.ctx.Pipe()
                w = _Worker(self.ctx.Process(target=_serve, args=(child, os.getpid()), daemon=False), conn)
                self.workers.append(w)
                w.proc.start()
                child.close()
            try:
                w.conn.send_bytes(job)
            except OSError:
                self._drop(w)
                return False
            w.job = index
        return True

    def wait(self) -> list[tuple[int, JobResult | None]]:
        """Wait for at least one busy worker to finish or die: [(job, its JobResult, or None if its worker died)]."""
        busy = [w for w in self.workers if w.job is not None]
        ready = set(mp_wait([w.conn for w in busy] + [w.proc.sentinel for w in busy]))
        out: list[tuple[int, JobResult | None]] = []
        for w in busy:
            if w.conn not in ready and w.proc.sentinel not in ready:
                continue
            i = w.job
            assert i is not None
            try:
                data = w.conn.recv_bytes() if w.conn.poll() else None
            except (EOFError, OSError):  # died before or while sending its result
                data = None
            if data == COMPILING:  # not its result: it compiles the kernels (still busy with job i)
                compiling(cache_dir())
                continue
            if data is None:
                self._drop(w)
                out.append((i, None))
                continue
            w.job = None
            try:
                _, value, error, wall = ForkingPickler.loads(data)
            except Exception as e:  # e.g. an exception class that cannot be rebuilt here
                value, error, wall = None, e, None
            out.append((i, JobResult(i, value, error, wall)))
        return out

    def _drop(self, w: _Worker) -> None:
        self.workers.remove(w)
        w.proc.kill()
        w.proc.join()
        w.conn.close()

    def close(self, graceful: bool) -> None:
        """End every worker: idle ones told to stop (``graceful``), else killed; each one reaped."""
        for w in self.workers:
            if graceful and w.job is None:
                with contextlib.suppress(OSError):
                    w.conn.send_bytes(b"")
            else:
                w.proc.kill()
        for w in self.workers:
            w.proc.join(timeout=5)
            if w.proc.exitcode is None:
                w.proc.kill()
                w.proc.join()
            w.conn.close()
        self.workers.clear()


def _serve(conn: Connection, parent: int) -> None:
    """A worker: run the jobs that come down ``conn``, send back (index, value, error, wall time); b"" ends it."""
    die_with_parent(parent)
    for sig in (signal.SIGINT, signal.SIGTERM):  # a Ctrl-C (or a stop) of the process group: the driver decides
        signal.signal(sig, signal.SIG_IGN)
    forward_notes(lambda: conn.send_bytes(COMPILING))  # the driver writes the compile note, above its bar
    while True:
        try:
            data = conn.recv_bytes()
        except (EOFError, OSError):  # the driver is gone
            return
        if not data:
            return
        try:
            fn, item, index = ForkingPickler.loads(data)
        except Exception as e:  # e.g. fn not importable here
            conn.send_bytes(ForkingPickler.dumps((None, None, _picklable(e), None)))
            continue
        value, error, wall = call_timed(fn, item)
        try:
            out = ForkingPickler.dumps((index, value, error, wall))
        except Exception as e:  # a result (or an error) that cannot be pickled
            out = ForkingPickler.dumps((index, None, _picklable(e), wall))
        conn.send_bytes(out)


def _picklable(e: BaseException) -> BaseException:
    try:
        ForkingPickler.dumps(e)
    except Exception:
        return RuntimeError(f"{type(e).__name__}: {e}")
    return e


def die_with_parent(parent: int, signum: int = signal.SIGKILL) -> None:
    """Pool worker initializer: the worker dies with its driver, even a driver killed with SIGKILL.

    On Linux the kernel sends the worker ``signum`` (SIGKILL; SIGTERM for a child that stops cleanly on it) when
    the driver exits (``prctl(PR_SET_PDEATHSIG)``); a driver that died before that was set (the worker's parent is
    no longer ``parent``) ends the worker at once.
    """
    if sys.platform.startswith("linux"):
        ctypes.CDLL(None, use_errno=True).prctl(1, int(signum))  # 1 = PR_SET_PDEATHSIG
    if os.getppid() != parent:
        os._exit(1)
