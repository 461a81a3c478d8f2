"""Stopping long work on the first SIGINT (Ctrl-C) or SIGTERM, keeping what it finished.

* :func:`stop_on_signals` is for a whole command: the first SIGINT or SIGTERM raises KeyboardInterrupt, which the
  command turns into one line saying what it kept; signals after it are ignored while it stops, so that the
  stop, which is short, is never itself cut short (no second Ctrl-C needed, and no traceback from one). The
  ``neurowalk`` command holds one block around everything it does (:mod:`neurowalk.__main__`); a command's own
  block inside it shares its record, so a signal is answered once.
* :func:`stop_status`: the exit status of a command a stop signal ended, 128 + the signal's number as a shell
  reports it: 130 for SIGINT, 143 for SIGTERM.
* :func:`deferred` guards a step that a signal must not cut in two (starting a pool's workers, storing a finished
  run, the files written at the end): SIGINT and SIGTERM that come during it are held and delivered when it ends.
* :func:`stop_requested`: a stop signal came. A KeyboardInterrupt can be lost where a library swallows it: amid
  numpy.random's import it is cleared silently (a run then went on to its end and exited 0); loops that wait for
  work and the runs themselves (``Streaming.stop``) look here as well, and :func:`interrupted` tells a command that
  an error it meets is such an interrupt in disguise. One raised inside a ctypes callback (numba compiles its
  runtime through llvmlite's, in every process, a moment after a command's start) is handed to
  ``sys.unraisablehook``, printed and dropped: inside a block that hook raises it again, unprinted, once the
  callback has returned.
"""

from __future__ import annotations

import _thread
import contextlib
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sys import UnraisableHookArgs
    from types import FrameType

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)

_requested: list[int] = []  # the stop signals the open blocks of :func:`stop_on_signals` got (empty: none)
_first: list[int] = []  # the first of them, kept after the blocks end (the exit status), until the next block
_depth = 0  # blocks of :func:`stop_on_signals` open (nested: the command's own inside the entry point's)
_dropped: list[bool] = []  # the KeyboardInterrupt of the first stop signal was swallowed: raise it again
_hooked: list[bool] = []  # the unraisable-exception hook of :func:`_raise_again` is running


def stop_requested() -> bool:
    """Whether the command running under :func:`stop_on_signals` was asked to stop."""
    return bool(_requested)


def stop_came() -> bool:
    """Whether a stop signal ended the last (or the open) :func:`stop_on_signals` block."""
    return bool(_first)


def stop_status() -> int:
    """The exit status of a command that a stop signal ended: 128 + the number of the first stop signal of the
    :func:`stop_on_signals` block open (or of the last one, once it ended): 130 for SIGINT, 143 for SIGTERM; 130
    where none came through such a block (a KeyboardInterrupt of Python's own Ctrl-C handler)."""
    return 128 + (_first[0] if _first else signal.SIGINT)


def interrupted(e: BaseException) -> bool:
    """Whether ``e``, raised under :func:`stop_on_signals`, is how a stop signal ended the work: a KeyboardInterrupt,
    or any error raised once a stop signal came (a library that turned the interrupt into an error of its own, e.g.
    an ImportError out of a C extension's import)."""
    return isinstance(e, KeyboardInterrupt) or stop_requested()


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextlib.contextmanager
def stop_on_signals(then: signal.Handlers | None = None) -> Iterator[None]:
    """Inside the block the first SIGINT or SIGTERM raises KeyboardInterrupt, later ones are ignored.

    Blocks nest: an inner one keeps the outer one's record (a signal the outer block answered is not answered
    again), which is forgotten when the outermost ends. ``then``: the handler both signals have after the block
    (e.g. ``signal.SIG_IGN``, so that a signal after a command's end does not interrupt the interpreter's exit);
    default: those they had before it. Outside the main thread (where Python cannot set signal handlers) the block
    changes nothing.
    """
    global _depth
    if not _in_main_thread():
        yield
        return

    def stop(signum: int, frame: FrameType | None) -> None:
        if _dropped:  # the interrupt raised again (:func:`_raise_again`), not a new signal
            if not _hooked:  # (not while that hook runs: it is inside the callback)
                _dropped.clear()
                raise KeyboardInterrupt
            return
        first = not _requested
        _requested.append(signum)
        if first:
            _first.append(signum)
            raise KeyboardInterrupt

    outermost = not _depth
    if outermost:
        _first.clear()
        hook, sys.unraisablehook = sys.unraisablehook, _raise_again(sys.unraisablehook)
    old = {}
    _depth += 1
    try:
        for sig in STOP_SIGNALS:
            old[sig] = signal.signal(sig, stop)
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler if then is None else then)
        _depth -= 1
        if outermost:
            _requested.clear()
            _dropped.clear()
            sys.unraisablehook = hook


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
    held: list[signal.Signals] = []

    def hold(signum: int, frame: FrameType | None) -> None:
        held.append(signal.Signals(signum))

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


def _raise_again(hook: Callable[[UnraisableHookArgs], object]) -> Callable[[UnraisableHookArgs], None]:
    """An unraisable-exception hook that, for the KeyboardInterrupt of a stop signal that a callback swallowed, asks
    for it again; anything else goes to ``hook``.

    The hook itself runs inside the callback, where a KeyboardInterrupt is swallowed again: a thread asks
    (``_thread.interrupt_main``, every millisecond) until the handler has raised it in Python code of the main thread
    that was not itself a callback's (a raise swallowed again comes back here and asks anew).
    """

    def unraisable(u: UnraisableHookArgs) -> None:
        if _requested and issubclass(u.exc_type, KeyboardInterrupt) and _in_main_thread():
            _hooked.append(True)
            try:
                _dropped.append(True)
                if not any(t.name == _ASKER and t.is_alive() for t in threading.enumerate()):
                    threading.Thread(target=_ask_again, args=(_first[0],), name=_ASKER, daemon=True).start()
            finally:
                _hooked.clear()
            return
        hook(u)

    return unraisable


_ASKER = "neurowalk-stop-again"


def _ask_again(signum: int) -> None:
    """Simulate ``signum`` in the main thread every millisecond while a swallowed interrupt waits to be raised."""
    while _dropped:
        _thread.interrupt_main(signal.Signals(signum))
        time.sleep(0.001)
