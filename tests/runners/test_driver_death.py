"""No worker outlives its driver: kill a sweep's driver (SIGKILL or SIGTERM) and its pool workers go too.

Both engines: the local pool (workers die by ``PR_SET_PDEATHSIG``) and a local Ray instance that the driver started
(Ray's own processes share the driver's fate).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import subprocess
import sys
import tempfile
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


RAY_DRIVER = """
import sys
sys.path.insert(0, sys.argv[1])
import sweep_fns
from neurowalk.runners.ray_backend import run_unordered
print("started", flush=True)
for d in run_unordered(sweep_fns.slow, [{"seed": s, "steps": 1, "sleep": 120} for s in range(4)], workers=2):
    pass
"""


def _descendants(pid: int) -> list[int]:
    out, todo = [], [pid]
    while todo:
        kids = _children(todo.pop())
        out += kids
        todo += kids
    return out


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


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_killing_a_ray_driver_leaves_no_ray_process(sig):
    pytest.importorskip("ray")
    here = str(Path(__file__).parent)
    ray_tmp = tempfile.mkdtemp(prefix="nwray", dir="/tmp")  # a short path: Ray's socket paths must fit 107 bytes
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p),
           "RAY_TMPDIR": ray_tmp}  # fmt: skip
    driver = subprocess.Popen([sys.executable, "-c", RAY_DRIVER, here], env=env, stdout=subprocess.PIPE)
    tree: list[int] = []
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:  # Ray starts, then its workers take the slow jobs
            time.sleep(0.5)
            tree = _descendants(driver.pid)
            busy = [p for p in tree if b"sweep_fns" in _cmdline(p) or b"ray::call_timed" in _cmdline(p)]
            if len(busy) >= 2:
                break
        assert len(tree) >= 3, "Ray did not start"
        time.sleep(1.0)
        tree = _descendants(driver.pid)
        os.kill(driver.pid, sig)
        driver.wait(timeout=60)
        # After SIGKILL, Ray's dashboard agent waits out its call to the (dead) GCS before it exits: about 60 s.
        deadline = time.monotonic() + 150
        while any(_alive(p) for p in tree) and time.monotonic() < deadline:
            time.sleep(0.2)
        left = [(p, _cmdline(p)[:80]) for p in tree if _alive(p)]
        assert not left, f"still running after the driver died: {left}"
    finally:
        if driver.poll() is None:
            driver.kill()
        for p in tree:  # whatever is left (the test has failed then), so that it does not outlive the test
            with contextlib.suppress(OSError):
                os.kill(p, signal.SIGKILL)
        shutil.rmtree(ray_tmp, ignore_errors=True)


def _cmdline(pid: int) -> bytes:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return b""
