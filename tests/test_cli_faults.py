"""What a machine does to a long run: a full disk, a failing write, an exception in the loop. One line, exit 1,
what is kept is on disk and said, no temp file left."""

from __future__ import annotations

import errno
import os
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from neurowalk.cli import main
from neurowalk.sim.trajectory import PartWriter

RUN = ["run", "--body", "surrogate", "--arena", "cluttered", "--quiet"]


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def _no_temp_files(folder: Path) -> None:
    left = list(folder.rglob(".*"))
    assert not left, left


def test_a_disk_full_while_writing_the_parts_keeps_those_written(tmp_path, monkeypatch, capsys):
    real = PartWriter.__call__

    def full_at_the_third(self: PartWriter, rows, start: int) -> None:
        if start == 20_000:
            raise OSError(errno.ENOSPC, "No space left on device", str(self.folder / "part-0000020000.npz"))
        real(self, rows, start)

    monkeypatch.setattr(PartWriter, "__call__", full_at_the_third)
    out = tmp_path / "run"
    assert main([*RUN, "--steps", "50000", "--out", str(out)]) == 1
    line = _one_line(capsys)
    assert "disk full writing" in line and "steps 0-19,999 kept" in line and "--resume" in line
    assert PartWriter(out / "trajectory.parts").count() == 20_000
    assert not (out / "summary.json").exists()
    _no_temp_files(out)
    monkeypatch.setattr(PartWriter, "__call__", real)
    assert main([*RUN, "--steps", "50000", "--out", str(out), "--resume"]) == 0  # starts again at step 0
    assert not (out / "trajectory.parts").exists()


def test_an_exception_in_the_loop_keeps_the_completed_steps(tmp_path, monkeypatch, capsys):
    from neurowalk.body.amosii import AmosII

    real, calls = AmosII.advance, []

    def breaks_at_step_250(self: AmosII) -> None:
        calls.append(1)
        if len(calls) == 250:
            raise RuntimeError("a bug")
        real(self)

    monkeypatch.setattr(AmosII, "advance", breaks_at_step_250)
    out = tmp_path / "run"
    assert main(["run", "--arena", "box", "--steps", "400", "--quiet", "--out", str(out)]) == 1
    line = _one_line(capsys)
    assert "RuntimeError: a bug" in line and "steps 0-248 kept" in line
    assert PartWriter(out / "trajectory.parts").count() == 249  # the completed steps, handed to the parts


def test_a_result_store_that_cannot_be_written_ends_a_sweep_in_one_line(tmp_path, monkeypatch, capsys):
    from neurowalk.runners.store import ResultStore

    def full(*args, **kwargs):
        raise sqlite3.OperationalError("database or disk is full")

    monkeypatch.setattr(ResultStore, "put", full)
    args = ["sweep", "--body", "surrogate", "--arena", "box", "--seeds", "2", "--steps", "50", "--workers", "1"]
    assert main([*args, "--out", str(tmp_path / "sw"), "--quiet"]) == 1
    line = _one_line(capsys)
    assert "disk is full" in line and str(tmp_path / "sw") in line


@pytest.fixture
def small_disk(tmp_path: Path):
    """A 1 MB tmpfs (where this machine lets the test mount one)."""
    mnt = tmp_path / "small"
    mnt.mkdir()
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root")
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(mnt)], capture_output=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {r.stderr.decode().strip()}")
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], check=False)


def test_a_run_on_a_full_filesystem_exits_1_in_one_line_and_keeps_its_parts(small_disk):
    out = small_disk / "run"
    cmd = [sys.executable, "-m", "neurowalk.cli", *RUN, "--steps", "2000000", "--out", str(out)]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    err = r.stderr.strip().splitlines()
    assert r.returncode == 1 and len(err) == 1, r.stderr
    assert "disk full" in err[0]
    held = PartWriter(out / "trajectory.parts").count()
    assert held > 0 and f"steps 0-{held - 1:,} kept" in err[0]
    _no_temp_files(out)


@pytest.mark.parametrize(
    ("body", "sig"),
    [("amosii", "SIGINT"), ("amosii", "SIGTERM"), ("surrogate", "SIGINT"), ("wheeled", "SIGTERM")],
)
def test_a_stopped_runs_summary_trajectory_and_picture_describe_the_same_steps(body, sig, tmp_path):
    import json
    import signal
    import time

    import numpy as np

    steps = "3000000" if body == "surrogate" else "30000"
    cmd = [sys.executable, "-m", "neurowalk.cli", "run", "--body", body, "--arena", "cluttered", "--steps", steps,
           "--quiet", "--out", str(tmp_path / "run")]  # fmt: skip
    p = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not (tmp_path / "run" / "trajectory.parts" / "run.json").exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(2.0)
    p.send_signal(getattr(signal, sig))
    _, err = p.communicate(timeout=60)
    assert p.returncode == 128 + getattr(signal, sig), err  # 130 for SIGINT, 143 for SIGTERM
    assert len(err.strip().splitlines()) == 1 and "interrupted" in err
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    with np.load(tmp_path / "run" / "trajectory.npz", allow_pickle=False) as z:
        rows = len(z["t"])
    assert 0 < summary["steps"] == rows < int(steps) and not summary["completed"]
    assert f"kept the {rows} completed steps" in err
    assert (tmp_path / "run" / "run.png").exists()
    _no_temp_files(tmp_path / "run")


def test_a_run_longer_than_the_machine_can_hold_is_refused_before_any_work(tmp_path, monkeypatch, capsys):
    from neurowalk.cli import run

    monkeypatch.setattr(run, "machine_memory", lambda: 2 * 10**9)
    assert main([*RUN, "--steps", "50000000", "--out", str(tmp_path / "run")]) == 2
    line = _one_line(capsys)
    assert "--steps 50,000,000" in line and "2.0 GB" in line
    assert not (tmp_path / "run").exists()


def test_figure_seeds_beyond_what_a_figure_holds_are_refused(tmp_path, capsys):
    assert main(["figure", "table2", "--seeds", "100001", "--out", str(tmp_path)]) == 2
    assert "--seeds must be in [1, 100,000]" in _one_line(capsys)
