"""What a command shows on stderr while it works: its progress bars, and one line while numba compiles its kernels.

numba compiles neurowalk's kernels the first time they run after an install, an upgrade or an edit, and caches them
(:mod:`neurowalk.compiled`); that first run of a command takes seconds longer than the next ones. Two things keep it
from being a silent wait:

- **The compile note** (:func:`compiling`): when a kernel really compiles (numba found no cached copy), a command
  says so in one line on stderr, once per process: ``neurowalk: compiling its kernels once for this version (...);
  cached in DIR``. It comes only from work that has begun (a kernel called, never while the command line is checked),
  so a bad input still gives its one line. It is written wherever stderr goes, a terminal (above the progress bar)
  or a log file (a plain line: a batch job's log says why its first run waits); ``NEUROWALK_COMPILE_NOTE=0`` writes
  it nowhere, and so does a command's ``--quiet`` (:func:`quiet_notes`). A pool worker that compiles hands the note
  to its driver (:func:`forward_notes`), which writes it, once, above its progress bar: one line, however many
  workers compile.
- **Progress bars** (:class:`Progress`): a tqdm bar whose rate and time left count from its first finished unit
  on. The first unit carries the one-off costs (the compile, the workers' start), which the bar's elapsed time
  shows but which are not the pace of the others: counted from the start, a run of seconds first showed minutes
  left. Until that first unit the time left shows as ``?``.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from tqdm import tqdm

#: The environment variable that turns the compile note off: "0" never writes it; unset (or any other value), it is
#: written wherever stderr goes.
NOTE_ENV = "NEUROWALK_COMPILE_NOTE"
#: What the first compile of a command's kernels costs, in words: the one-off wall time of the commands of the
#: README's first steps on a cold cache over a warm one, docs/benchmarks/compile.json
#: (``python benchmarks/bench_compile.py``; 2 cores, shared with other work).
COMPILE_TIME = "about 10-30 s"

_said = False  # this process has written (or forwarded, or let pass) its note
_quiet = False  # --quiet: no note from this process
_forward: Callable[[], None] | None = None  # a pool worker's way to its driver


def compiling(where: Path) -> None:
    """A neurowalk kernel is being compiled (no cached copy in ``where``): the note, the first time in this process.

    Called by :mod:`neurowalk.compiled` as numba starts compiling one. A pool worker with :func:`forward_notes` hands
    it to its driver; another child process (of multiprocessing: a worker of some other pool) keeps quiet.
    """
    global _said
    if _said:
        return
    _said = True
    # A note never stops the work: a driver gone (its pipe closed), a stderr closed or a reader gone (broken pipe).
    with contextlib.suppress(OSError, ValueError):
        if _forward is not None:
            _forward()
            return
        if multiprocessing.parent_process() is not None or not _wanted():
            return
        line = f"neurowalk: compiling its kernels once for this version ({COMPILE_TIME}); cached in {where}"
        tqdm.write(line, file=sys.stderr)  # above any progress bar on stderr, which is drawn again below it
        sys.stderr.flush()


def _wanted() -> bool:
    """Whether this process writes the note: not ``--quiet``, and as :data:`NOTE_ENV` says (see the module doc)."""
    return not _quiet and os.environ.get(NOTE_ENV, "").strip() != "0" and sys.stderr is not None


@contextlib.contextmanager
def quiet_notes(quiet: bool = True) -> Iterator[None]:
    """No compile note from this process inside the block where ``quiet`` (a command's ``--quiet``)."""
    global _quiet
    before = _quiet
    _quiet = before or quiet
    try:
        yield
    finally:
        _quiet = before


def forward_notes(send: Callable[[], None]) -> None:
    """In a pool worker: hand the compile note to the driver with ``send()`` (once) instead of writing it here."""
    global _forward
    _forward = send


class Progress(tqdm):  # type: ignore[type-arg]
    """A tqdm bar whose rate and time left count from its first finished unit on (see the module doc).

    Its arguments are tqdm's. The elapsed time is the whole wait; the rate (units per second) is that of the units
    after the first over the time since it finished, shown as ``?`` (and the time left too) until there is one.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self._first: tuple[float, float] | None = None  # (time.time() in s, count) when the first unit finished
        super().__init__(*args, **kwargs)

    def update(self, n: float | None = 1) -> bool | None:
        """Count ``n`` more units done (tqdm's ``update``); the first that counts some starts the rate's clock."""
        if self._first is None and n and not self.disable:
            self._first = (time.time(), self.n + n)
        return super().update(n)

    @property
    def format_dict(self) -> dict[str, Any]:
        """tqdm's fields, the rate (units/s) counted from the first finished unit (0, shown ``?``, until one more)."""
        d = super().format_dict
        if self._first is not None:  # (also as it closes: tqdm's close sets ``disable`` before its last line)
            t1, n1 = self._first
            dt = time.time() - t1
            d["rate"] = (self.n - n1) / dt if self.n > n1 and dt > 0 else 0.0
        return d
