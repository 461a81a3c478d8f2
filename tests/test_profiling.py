"""Where a command's time goes (:mod:`neurowalk.profiling`): parts summed over its process and forked workers."""

from __future__ import annotations

import json
import multiprocessing
import os
from pathlib import Path

import pytest

from neurowalk import profiling
from neurowalk.sim.episode import EpisodeConfig, run_episode


def _worker_adds(out: str) -> None:
    """A forked worker: it starts from zero, adds its own seconds and writes them when it ends."""
    os.environ[profiling.ENV] = out
    assert profiling.totals()["seconds"] == {}
    profiling.add("physics", 2.0, count=100)


def test_a_forked_worker_writes_its_own_sums_only(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(profiling, "_seconds", {})
    monkeypatch.setattr(profiling, "_counts", {})
    profiling.add("physics", 5.0, count=7)  # the parent's: not the worker's to write
    ctx = multiprocessing.get_context("fork")
    p = ctx.Process(target=_worker_adds, args=(str(tmp_path),))
    p.start()
    p.join()
    assert p.exitcode == 0
    files = list(tmp_path.glob("profile-*.json"))
    assert [f.name for f in files] == [f"profile-{p.pid}.json"]
    assert json.loads(files[0].read_text()) == {"seconds": {"physics": 2.0}, "counts": {"physics": 100}}
    (tmp_path / "profile-1.json").write_text(json.dumps({"seconds": {"physics": 1.0, "drawing": 0.5}, "counts": {}}))
    total = profiling.read_profile(tmp_path, wall_s=10.0)
    assert total["processes"] == 2 and total["seconds"] == {"physics": 3.0, "drawing": 0.5}
    assert total["physics_steps"] == 100 and total["physics_steps_per_s"] == round(100 / 3.0)
    assert total["wall_time_s"] == 10.0


def test_a_run_counts_its_physics_steps_and_control(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(profiling, "_seconds", {})
    monkeypatch.setattr(profiling, "_counts", {})
    ep = run_episode(EpisodeConfig(steps=50))
    t = profiling.totals()
    substeps = round(1 / (ep.config.control_hz * 0.01))  # the default physics step: 0.01 s
    assert t["counts"]["physics"] == 50 * substeps
    assert t["seconds"]["physics"] > 0 and t["seconds"]["control"] > 0 and t["seconds"]["summary"] > 0
    assert t["seconds"]["physics"] + t["seconds"]["control"] < ep.summary["wall_time_s"] * 1.01 + 0.01
