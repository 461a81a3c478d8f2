"""No worker outlives its driver: kill a sweep's driver (SIGKILL or SIGTERM) and its pool workers go too."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

DRIVER = """
import sys
sys.path.insert(0, sys.argv[1])
import sweep_fns
from neurowalk.runners.local import run_unordered
for d in run_unordered(sweep_fns.slow, [{"seed": s, "steps": 1, "sleep": 60} for s in range(4)], workers=2):
    pass
"""


def _children(pid: int) -> list[int]:
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            out.append(int(stat.parent.name))
    return out


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"  # a zombie is dead, only not yet reaped


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_killing_the_driver_leaves_no_worker(sig):
    here = str(Path(__file__).parent)
    driver = subprocess.Popen([sys.executable, "-c", DRIVER, here])
    try:
        workers: list[int] = []
        for _ in range(200):  # the pool starts its workers (the resource tracker is not one)
            time.sleep(0.05)
            workers = [
                p for p in _children(driver.pid) if b"resource_tracker" not in Path(f"/proc/{p}/cmdline").read_bytes()
            ]
            if len(workers) >= 2:
                break
        assert len(workers) >= 2, "the pool did not start"
        time.sleep(0.5)  # the workers are running their jobs
        os.kill(driver.pid, sig)
        driver.wait(timeout=30)
        deadline = time.monotonic() + 10
        while any(_alive(p) for p in workers) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not any(_alive(p) for p in workers)
    finally:
        if driver.poll() is None:
            driver.kill()
