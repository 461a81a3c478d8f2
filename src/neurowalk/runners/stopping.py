"""Stopping long work on the first SIGINT (Ctrl-C) or SIGTERM, keeping what it finished.

* :func:`stop_on_signals` is for a whole command: the first SIGINT or SIGTERM raises KeyboardInterrupt, which the
  command turns into one line saying what it kept; signals after it are ignored while it stops, so that the
  stop, which is short, is never itself cut short (no second Ctrl-C needed, and no traceback from one).
* :func:`deferred` guards a step that a signal must not cut in two (starting a pool's workers, storing a finished
  run, the files written at the end): SIGINT and SIGTERM that come during it are held and delivered when it ends.
* :func:`stop_requested`: a stop signal came. A KeyboardInterrupt can be lost where a library swallows it (e.g.
  one raised inside a ctypes callback is printed and dropped); loops that wait for work look here as well, and
  :func:`interrupted` tells a command that an error it meets is such an interrupt in disguise.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from typing import Any

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)

_requested: list[int] = []  # the stop signals :func:`stop_on_signals` got (empty: none)


def stop_requested() -> bool:
    """Whether the command running under :func:`stop_on_signals` was asked to stop."""
    return bool(_requested)


def interrupted(e: BaseException) -> bool:
    """Whether ``e``, raised under :func:`stop_on_signals`, is how a stop signal ended the work: a KeyboardInterrupt,
    or any error raised once a stop signal came (a library that turned the interrupt into an error of its own, e.g.
    an ImportError out of a C extension's import)."""
    return isinstance(e, KeyboardInterrupt) or stop_requested()


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """Inside the block the first SIGINT or SIGTERM raises KeyboardInterrupt, later ones are ignored.

    Outside the main thread (where Python cannot set signal handlers) the block changes nothing.
    """
    if not _in_main_thread():
        yield
        return

    def stop(signum: int, frame: Any) -> None:
        first = not _requested
        _requested.append(signum)
        if first:
            raise KeyboardInterrupt

    old = {sig: signal.signal(sig, stop) for sig in STOP_SIGNALS}
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        _requested.clear()


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """Hold SIGINT and SIGTERM during the block; deliver them (each once) to the handlers in place when it ends.

    A process forked inside the block starts with the holding handler, so a signal that reaches it before it sets
    its own handlers does nothing. Signals set to be ignored, or handled outside Python, are left as they are;
    outside the main thread the block changes nothing.
    """
    if not _in_main_thread():
        yield
        return
    held: list[int] = []

    def hold(signum: int, frame: Any) -> None:
        held.append(signum)

    old = {}
    for sig in STOP_SIGNALS:
        handler = signal.getsignal(sig)
        if handler is not None and handler != signal.SIG_IGN:
            old[sig] = signal.signal(sig, hold)
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        for sig in dict.fromkeys(held):
            signal.raise_signal(sig)
