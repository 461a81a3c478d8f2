"""Ctrl-C on the test suite leaves no process of it running, Ray's included (:mod:`leftovers`)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from leftovers import group, is_ray

pytest.importorskip("ray")
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
ROOT = Path(__file__).parents[1]


def test_ctrl_c_on_the_suite_leaves_no_process(tmp_path: Path):
    """The suite's Ray tests, on two xdist workers, stopped as a terminal's Ctrl-C stops them (SIGINT to the
    whole process group) once a local Ray instance runs: every process of the group is gone within seconds."""
    cmd = [sys.executable, "-m", "pytest", "-n", "2", "-p", "no:cacheprovider", "tests/runners/test_ray_backend.py"]
    p = subprocess.Popen(
        cmd,
        cwd=ROOT,
        start_new_session=True,  # its own group, as a shell's job
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # as a terminal's job gets it
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 120
    while not any("raylet" in " ".join(a) for a in group(p.pid).values()):
        assert p.poll() is None and time.monotonic() < deadline, "no Ray instance started"
        time.sleep(0.2)
    time.sleep(1.0)  # its agents started too
    os.killpg(p.pid, signal.SIGINT)
    assert p.wait(60) != 0
    deadline = time.monotonic() + 10
    while group(p.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    left = group(p.pid)
    for pid in left:  # not to leave them to the next test either
        os.kill(pid, signal.SIGKILL)
    ray = sum(map(is_ray, left.values()))
    assert not left, f"left running ({ray} of Ray's): {[' '.join(a)[:80] for a in left.values()]}"
