"""A stopped physics run goes on from its checkpoint, bit for bit the run that was never stopped."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from neurowalk.sim.checkpoint import Checkpoint
from neurowalk.sim.episode import EpisodeConfig, Resume, Streaming, run_episode
from neurowalk.sim.trajectory import Trajectory

CFG = EpisodeConfig(arena="random", arena_opts={"n_boxes": 8, "extent": 3.0}, steps=300, seed=5, reflexes=True,
                    backbone=True)  # fmt: skip


def _same(a: Trajectory, b: Trajectory) -> None:
    for f in ("t", "pose", "inputs", "outputs", "b", "q", "targets", "joint_angles", "us_distance", "qpos"):
        np.testing.assert_array_equal(getattr(a, f), getattr(b, f), err_msg=f)


def test_resume_from_a_checkpoint_is_bit_for_bit_the_whole_run():
    whole = run_episode(CFG).trajectory
    saved: dict[int, Checkpoint] = {}
    pieces: list[tuple[int, Trajectory]] = []
    run_episode(
        CFG,
        stream=Streaming(
            chunk=100,
            sink=lambda rows, start: pieces.append((start, _copy(rows))),
            checkpoint=lambda ckpt: saved.setdefault(ckpt.step, ckpt),
        ),
    )
    assert sorted(saved) == [100, 200] and [s for s, _ in pieces] == [0, 100, 200]
    resumed = run_episode(CFG, stream=Streaming(chunk=100, resume=Resume(saved[200], pieces[:2]))).trajectory
    _same(resumed, whole)


def _copy(rows: Trajectory) -> Trajectory:
    return rows.map(np.copy)


@pytest.mark.slow
@pytest.mark.parametrize("after_checkpoint", [False, True], ids=["before-the-first-checkpoint", "after-it"])
def test_kill_9_then_resume_gives_the_uninterrupted_trajectory(after_checkpoint, tmp_path: Path):
    """SIGKILL before the first checkpoint (a few thousand steps in) and a few thousand steps after it (step 10,000),
    then --resume: the trajectory equals an uninterrupted run's."""
    steps = "15000" if after_checkpoint else "8000"  # past the first checkpoint (10,000) where it is to be met
    args = ["--arena", "difficult", "--controller", "plastic", "--steps", steps, "--seed", "3", "--quiet"]
    cli = [sys.executable, "-m", "neurowalk.cli", "run"]
    killed = tmp_path / "killed"
    p = subprocess.Popen([*cli, *args, "--out", str(killed)])
    checkpoint = killed / "trajectory.parts" / "checkpoint.npz"
    deadline = time.monotonic() + 300
    if after_checkpoint:
        while not checkpoint.exists() and time.monotonic() < deadline and p.poll() is None:
            time.sleep(0.2)
        assert checkpoint.exists(), "no checkpoint written"
        time.sleep(2.0)  # on past it
    else:
        while not (killed / "trajectory.parts" / "run.json").exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        time.sleep(2.0)  # a few thousand steps in
    assert p.poll() is None, "the run ended before it was killed"
    os.kill(p.pid, signal.SIGKILL)
    p.wait()
    assert checkpoint.exists() == after_checkpoint
    assert not (killed / "trajectory.npz").exists()
    assert subprocess.run([*cli, "--out", str(killed), "--quiet"], capture_output=True).returncode == 2  # refused
    assert subprocess.run([*cli, "--resume", "--out", str(killed), "--quiet"]).returncode == 0
    whole = tmp_path / "whole"
    assert subprocess.run([*cli, *args, "--out", str(whole)]).returncode == 0
    _same(Trajectory.load(killed / "trajectory.npz"), Trajectory.load(whole / "trajectory.npz"))
    assert not (killed / "trajectory.parts").exists()
