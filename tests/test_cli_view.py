"""`neurowalk view`'s bad input: one line naming the fault, exit status 2, nothing written."""

from __future__ import annotations

import shutil
import socket
import subprocess
import sys
from pathlib import Path

import pytest


def _view(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "neurowalk", "view", *args], capture_output=True, text=True, cwd=cwd)


@pytest.fixture(scope="module")
def run_dir(run_folder) -> Path:
    return run_folder("--arena", "box", "--steps", "50")


def test_bad_input_gets_one_line_and_status_2(tmp_path: Path, run_dir: Path):
    damaged = tmp_path / "damaged"
    shutil.copytree(run_dir, damaged)
    (damaged / "trajectory.npz").write_bytes(b"not an npz")
    cases = {
        (): "view needs RUN_DIR",
        (str(tmp_path / "none"),): "is not a folder",
        (str(tmp_path),): "is not a run's folder",
        (str(damaged),): "damaged or incomplete arrays",
        (str(run_dir), "--port", "70000"): "--port must be 1-65535",
        (str(run_dir), "--export", "x.png"): "name it FILE.html",
        (str(run_dir), "--export", "no/such/folder/x.html"): "its folder does not exist",
        (str(run_dir), "--native"): "drop",
    }
    before = sorted(p.name for p in tmp_path.rglob("*"))
    for args, words in cases.items():
        done = _view(*args, cwd=tmp_path)
        lines = done.stderr.strip().splitlines()
        assert done.returncode == 2 and len(lines) == 1 and words in lines[0], (args, done.stderr)
    assert sorted(p.name for p in tmp_path.rglob("*")) == before  # nothing written


def test_a_port_in_use_gets_one_line(tmp_path: Path, run_dir: Path):
    pytest.importorskip("viser", reason="the web viewer needs the `web` extra (viser)")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        port = s.getsockname()[1]
        done = _view(str(run_dir), "--port", str(port), cwd=tmp_path)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1 and f"127.0.0.1:{port}" in lines[0] and "--port" in lines[0]
