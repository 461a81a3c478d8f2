"""A Ray sweep survives a lost node with its default flags: a cluster of two local nodes, one killed midway while it
runs a job (its raylet gone, as when a machine drops out), and the sweep ends with every run done and exit status 0."""

from __future__ import annotations

import contextlib
import json
import os
import re
import signal
import socket
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("ray")
pytestmark = [pytest.mark.slow, pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")]

RAY = str(Path(sys.executable).parent / "ray")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _pids(word: str) -> dict[int, str]:
    """The processes whose command line holds ``word``: pid -> command line."""
    out = {}
    for cmd in Path("/proc").glob("[0-9]*/cmdline"):
        with contextlib.suppress(OSError):
            line = cmd.read_bytes().replace(b"\0", b" ").decode(errors="replace")
            if word in line:
                out[int(cmd.parent.name)] = line
    return out


def _agents(raylets: set[int]) -> list[int]:
    """The processes a raylet of ``raylets`` started (its agents rename themselves ``ray::...``; their environment
    names their raylet)."""
    out = []
    for env in Path("/proc").glob("[0-9]*/environ"):
        with contextlib.suppress(OSError):
            found = re.search(rb"RAY_RAYLET_PID=(\d+)", env.read_bytes())
            if found and int(found.group(1)) in raylets:
                out.append(int(env.parent.name))
    return out


def _running(raylet: int) -> bool:
    """A worker of ``raylet``'s node runs a sweep's job now (Ray names a worker by its task: ``ray::call_timed``;
    an idle one is ``ray::IDLE``)."""
    for pid in _agents({raylet}):
        with contextlib.suppress(OSError):
            if Path(f"/proc/{pid}/cmdline").read_bytes().startswith(b"ray::call_timed"):
                return True
    return False


def _raylets(temp: Path) -> list[int]:
    """The raylets (one per node) of the cluster whose session files are in ``temp``."""
    return [p for p, line in _pids(str(temp)).items() if line.split(" ", 1)[0].endswith("/raylet")]


def _done(store: Path) -> int:
    if not store.is_file():
        return 0
    db = sqlite3.connect(f"file:{store}?mode=ro", uri=True)
    try:
        return int(db.execute("SELECT count(*) FROM runs WHERE status = 'ok'").fetchone()[0])
    except sqlite3.Error:  # not written yet
        return 0
    finally:
        db.close()


@pytest.mark.parametrize("retries", [None, "0"], ids=["default flags", "--retries 0"])
def test_a_ray_sweep_survives_a_lost_node_with_default_flags(retries: str | None, tmp_path: Path) -> None:
    """With its default flags the sweep runs the lost node's jobs again on the other; with ``--retries 0`` the same
    loss fails them (so the node was lost while it ran some), and the last line says how to run them again."""
    port = _free_port()
    temp = Path("/tmp") / f"nwray{port}"  # short: Ray's socket paths must fit in 107 bytes
    env = {**os.environ, "RAY_USAGE_STATS_ENABLED": "0", "RAY_AUTH_MODE": "disabled"}  # a local test cluster
    address = f"127.0.0.1:{port}"
    start = [RAY, "start", "--num-cpus=1", "--disable-usage-stats"]
    raylets: set[int] = set()
    try:
        subprocess.run([*start, "--head", f"--port={port}", "--include-dashboard=false", f"--temp-dir={temp}"],
                       env=env, check=True, capture_output=True, timeout=120)  # fmt: skip
        before = set(_raylets(temp))
        subprocess.run([*start, f"--address={address}"], env=env, check=True, capture_output=True, timeout=120)
        raylets = set(_raylets(temp))
        second = sorted(raylets - before)
        assert len(second) == 1, f"the second node's raylet: {second}"
        out = tmp_path / "sweep"
        cmd = [sys.executable, "-m", "neurowalk", "sweep", "--arena", "box", "--seeds", "6", "--steps", "600",
               "--backend", "ray", "--address", address, "--out", str(out), "--quiet"]  # fmt: skip
        cmd += ["--retries", retries] if retries is not None else []
        sweep = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + 300  # the loss comes once a run is done, while the node runs a job of its own
        while (_done(out / "results.sqlite") < 1 or not _running(second[0])) and sweep.poll() is None:
            assert time.monotonic() < deadline, "no job ran on the second node"
            time.sleep(0.05)
        assert sweep.poll() is None, f"the sweep ended before a node was lost: {sweep.communicate()}"
        for pid in second:  # the node drops out midway: its raylet and, with it, its workers
            os.kill(pid, signal.SIGKILL)
        last, stderr = sweep.communicate(timeout=600)
        info = json.loads((out / "sweep.json").read_text())
        said = [line for line in stderr.splitlines() if line.startswith("neurowalk: Ray: ")]  # the loss, a line each
        assert "(raylet)" not in last + stderr and "state-dump" not in last + stderr, (last + stderr)[-3000:]
        if retries is None:
            assert sweep.returncode == 0, stderr[-3000:]
            assert info["counts"]["ok"] == 6 and info["counts"]["error"] == 0, info
            assert _done(out / "results.sqlite") == 6 and "6 runs: 0 already done, 6 ok, 0 failed" in last
            assert stderr.strip().splitlines() == said and 1 <= len(said) <= 4, stderr[-3000:]
            assert any("Raylet is terminated" in line for line in said) and len(set(said)) == len(said)
            return
        failed = info["counts"]["error"]
        assert sweep.returncode == 1 and failed >= 1 and all("WorkerDiedError" in f["error"] for f in info["failures"])
        assert last.strip().endswith(f"; run the same command again to run the {failed} failed again"), last
    finally:  # only this cluster's processes (another test's Ray may be running), its raylets' agents too
        for pid in [*_pids(str(temp)), *_agents(raylets)]:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
