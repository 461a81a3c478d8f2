"""The processes a test run leaves behind: found by process group in /proc (Linux), Ray's ended.

Ctrl-C reaches every process of the terminal's foreground group at once: pytest, its xdist workers, and the local
Ray instances the Ray tests start (gcs_server, raylet and the agents raylet starts). Raylet dies at once, and its
agents, which watch it, take a minute or two to give up on the dead cluster before they exit. The suite ends
every Ray process of its group when it ends (``conftest.pytest_unconfigure``), so none outlives it.
"""

from __future__ import annotations

import contextlib
import os
import signal
import time
from pathlib import Path


def group(pgid: int) -> dict[int, list[str]]:
    """``{pid: argv}`` of the live processes in process group ``pgid`` (zombies left out), but this one."""
    found = {}
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit() or int(proc.name) == os.getpid():
            continue
        try:
            stat = (proc / "stat").read_text()
            argv = (proc / "cmdline").read_bytes().decode(errors="replace").split("\0")
        except OSError:  # gone meanwhile
            continue
        fields = stat[stat.rindex(")") + 2 :].split()  # after "pid (comm) ": state, ppid, pgrp, ...
        if fields[0] != "Z" and int(fields[2]) == pgid:
            found[int(proc.name)] = [a for a in argv if a]
    return found


def is_ray(argv: list[str]) -> bool:
    """Whether a command line is one of Ray's processes (a ``ray::`` worker or agent, or a program of the ray
    package: gcs_server, raylet, the dashboard, the monitors)."""
    return bool(argv) and (argv[0].startswith("ray::") or any("site-packages/ray/" in a for a in argv))


def end_ray(pgid: int, grace_s: float = 3.0) -> list[int]:
    """SIGTERM every Ray process of group ``pgid``, SIGKILL those still there after ``grace_s``; their pids."""
    pids = [pid for pid, argv in group(pgid).items() if is_ray(argv)]
    for sig in (signal.SIGTERM, signal.SIGKILL):
        for pid in pids:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, sig)
        deadline = time.monotonic() + grace_s
        while sig == signal.SIGTERM and time.monotonic() < deadline and set(pids) & set(group(pgid)):
            time.sleep(0.1)
    return pids
