"""runners/stopping.py: the first stop signal raises KeyboardInterrupt once, blocks nest, and the exit status names
the signal (130 SIGINT, 143 SIGTERM)."""

from __future__ import annotations

import os
import signal

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
