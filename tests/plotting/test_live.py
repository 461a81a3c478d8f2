"""A run shown live (`run --web`): the rows kept chunk by chunk make the replay of the finished run, the page
follows the run, and the command serves while it runs and after, until Ctrl-C."""

from __future__ import annotations

import dataclasses
import json
import signal
import subprocess
import sys
import time
from pathlib import Path
from urllib.request import urlopen

import numpy as np
import pytest

pytest.importorskip("viser", reason="the web viewer needs the `web` extra (viser)")

from neurowalk.plotting.live import LivePage, LiveRun
from neurowalk.plotting.replay import load_replay, world_config
from neurowalk.plotting.web import free_port
from neurowalk.sim.trajectory import Trajectory


@pytest.fixture(scope="module")
def run_dir(run_folder) -> Path:
    return run_folder("--arena", "narrow-passage", "--steps", "400")


def _feed(live: LiveRun, tr: Trajectory, chunk: int) -> None:
    for start in range(0, len(tr.t), chunk):
        live(tr.rows(start, min(start + chunk, len(tr.t))), start)


def test_rows_kept_chunk_by_chunk_make_the_runs_replay(run_dir: Path):
    whole = load_replay(run_dir)
    summary = json.loads((run_dir / "summary.json").read_text())
    tr = Trajectory.load(run_dir / "trajectory.npz")
    seen: list[int] = []
    live = LiveRun(
        dataclasses.replace(world_config(summary), steps=len(tr.t)), then=lambda rows, start: seen.append(start)
    )
    _feed(live, tr, chunk=37)  # chunks that do not line up with anything
    assert live.done == len(tr.t) and seen == list(range(0, len(tr.t), 37))  # handed on, in order
    r = live.replay
    for name in ("t", "path", "inputs", "outputs", "b", "q", "pos", "quat", "ray_from", "ray_to"):
        assert np.array_equal(getattr(r, name), getattr(whole, name)), name


def test_the_page_follows_the_run(run_dir: Path):
    summary = json.loads((run_dir / "summary.json").read_text())
    tr = Trajectory.load(run_dir / "trajectory.npz")
    live = LiveRun(dataclasses.replace(world_config(summary), steps=len(tr.t)))
    page = LivePage(live, port=free_port())
    try:
        live(tr.rows(0, 150), 0)
        deadline = time.monotonic() + 10
        while int(page.slider.value) != 149 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert int(page.slider.value) == 149 and page.available == 150  # it shows the newest step
        page.follow.value = False
        live(tr.rows(150, 300), 150)
        time.sleep(1.0)
        assert int(page.slider.value) == 149 and page.available == 300  # not following: it stays, the rest grows
        page.go(10_000)
        assert int(page.slider.value) == 299  # at most the newest step
        live(tr.rows(300, 400), 300)
        page.finished()
        assert int(page.slider.value) == 399 and page.available == 400
    finally:
        page.close()


def test_run_web_serves_while_and_after_it_runs(tmp_path: Path):
    port = free_port()
    cmd = [sys.executable, "-m", "neurowalk", "run", "--arena", "box", "--steps", "300", "--web", "--port", str(port),
           "--out", str(tmp_path / "run"), "--quiet"]  # fmt: skip
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        lines = []
        while not any("Ctrl-C stops" in line for line in lines):
            line = proc.stderr.readline()
            assert line, f"the command ended early: {lines}"
            lines.append(line)
        assert f"http://127.0.0.1:{port}" in lines[0]  # where the page is, first
        with urlopen(f"http://127.0.0.1:{port}/", timeout=10) as page:
            assert page.status == 200 and b"<html" in page.read(2000).lower()
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=30)
    finally:
        proc.kill()
    assert proc.returncode == 0 and "box/plastic: 300 steps" in out
    assert {p.name for p in (tmp_path / "run").iterdir()} >= {"summary.json", "trajectory.npz", "run.png"}
