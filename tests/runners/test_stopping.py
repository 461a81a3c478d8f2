"""runners/stopping.py: the first stop signal raises KeyboardInterrupt once, blocks nest, and the exit status names
the signal (130 SIGINT, 143 SIGTERM)."""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import signal
import sys
import time

import pytest

from neurowalk.runners.stopping import stop_on_signals, stop_requested, stop_status


@pytest.mark.parametrize(("sig", "status"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_the_first_signal_raises_once_and_gives_its_exit_status(sig, status):
    before = signal.getsignal(signal.SIGTERM)
    with stop_on_signals():
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), sig)
        os.kill(os.getpid(), signal.SIGINT)  # a second one is ignored while the command stops
        os.kill(os.getpid(), signal.SIGTERM)
        assert stop_requested() and stop_status() == status
    assert not stop_requested() and stop_status() == status  # the status is kept after the block, until the next
    assert signal.getsignal(signal.SIGTERM) is before
    with stop_on_signals():
        assert stop_status() == 130  # none came yet (Python's own Ctrl-C: 130)


def test_an_inner_block_keeps_the_outer_ones_record():
    with stop_on_signals(then=signal.SIG_IGN):
        with stop_on_signals(), pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGTERM)
        os.kill(os.getpid(), signal.SIGINT)  # answered once: not again after the inner block
        assert stop_status() == 143
    try:
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN  # `then`: a signal after the command is ignored
        assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
        assert not stop_requested() and stop_status() == 143  # the command's exit status, after its block
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


def test_an_interrupt_a_ctypes_callback_swallowed_is_raised_again_unprinted(capfd):
    """A stop signal answered inside a ctypes callback (numba's runtime is compiled through llvmlite's at every
    start): ctypes prints that KeyboardInterrupt and drops it; in a block it is raised once the callback returns."""
    libc = ctypes.CDLL(ctypes.util.find_library("c"))
    values = (ctypes.c_int * 4)(3, 1, 2, 0)
    compare = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_int))

    def signalled(a, b):  # a signal that comes while the callback runs
        if not stop_requested():
            os.kill(os.getpid(), signal.SIGTERM)
        return a[0] - b[0]

    with stop_on_signals():
        with pytest.raises(KeyboardInterrupt):
            libc.qsort(values, len(values), ctypes.sizeof(ctypes.c_int), compare(signalled))
            deadline = time.monotonic() + 10
            while time.monotonic() < deadline:  # (raised within a few ms)
                pass
            pytest.fail("the swallowed interrupt was not raised again")
        assert stop_status() == 143
        libc.qsort(values, len(values), ctypes.sizeof(ctypes.c_int), compare(signalled))  # no second stop
    assert "Exception ignored" not in capfd.readouterr().err
    assert sorted(values) == [0, 1, 2, 3]


def test_other_unraisable_exceptions_go_to_the_hook_in_place(monkeypatch):
    seen = []
    monkeypatch.setattr(sys, "unraisablehook", lambda u: seen.append(u.exc_type))

    class Broken:
        def __del__(self):
            raise ValueError("in __del__")

    with stop_on_signals():
        Broken()
    assert seen == [ValueError]
    hook = sys.unraisablehook
    with stop_on_signals():
        pass
    assert sys.unraisablehook is hook  # put back after the block
