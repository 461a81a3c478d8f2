"""When a ``neurowalk`` process is ready for a stop signal: moments to send one, measured from the process itself.

A test that signals a command "0.05 s after its start" hits a different phase on a loaded machine than on an idle
one (and, before the command's handlers are in place, the interpreter's own: a traceback, or death by the signal).
The moments here are read from the process instead: its readiness is the first moment ``/proc/PID/status`` shows
both SIGINT and SIGTERM in its ``SigCgt`` mask, i.e. the command's entry point (``neurowalk/__main__.py``) has put
its handlers in place; a Python process catches SIGINT from its start, SIGTERM only once ours are set.
"""

from __future__ import annotations

import signal
import subprocess
import time
from pathlib import Path

STOP_MASK = (1 << (signal.SIGINT - 1)) | (1 << (signal.SIGTERM - 1))


def catches_stop_signals(pid: int) -> bool:
    """Whether process ``pid`` has handlers of its own for SIGINT and SIGTERM (False once it has ended)."""
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    for line in text.splitlines():
        if line.startswith("SigCgt:"):
            return int(line.split()[1], 16) & STOP_MASK == STOP_MASK
    return False


def wait_ready(proc: subprocess.Popen, timeout: float = 120.0) -> float | None:
    """Poll until ``proc`` catches SIGINT and SIGTERM; the ``time.monotonic()`` of that moment, or None if the process
    ended first. Fails the test if it is not ready within ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while proc.poll() is None:
        if catches_stop_signals(proc.pid):
            return time.monotonic()
        if time.monotonic() > deadline:
            proc.kill()
            proc.communicate()
            raise AssertionError(f"{proc.args} set no handlers for SIGINT and SIGTERM within {timeout} s")
        time.sleep(0.0005)
    return None


def sleep_until(t: float) -> None:
    """Wait until ``time.monotonic()`` reaches ``t`` (a few ms: no coarser than the scheduler lets it be)."""
    while (left := t - time.monotonic()) > 0:
        time.sleep(min(left, 0.001))
