"""Checkpoints are arrays and JSON: they round-trip, continue bit for bit, and nothing in a results folder runs code."""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import numpy as np
import pytest

from neurowalk.cli import main
from neurowalk.sim.checkpoint import FORMAT, Checkpoint, CheckpointError, capture, restore
from neurowalk.sim.episode import EpisodeConfig, build, seeds
from neurowalk.sim.trajectory import Trajectory

RUN = ["run", "--arena", "box", "--steps", "40", "--quiet"]


class _Evil:
    """Unpickling this creates a file: proof that a pickle was loaded."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def __reduce__(self) -> tuple:
        return (Path.touch, (self.path,))


def _unfinished(folder: Path) -> Path:
    """A folder as a physics run leaves it before its end: run.json and one part (from an interrupted run)."""
    assert main([*RUN, "--out", str(folder)]) == 0
    parts = folder / "trajectory.parts"
    parts.mkdir()
    cfg = json.loads((folder / "summary.json").read_text())
    spec = EpisodeConfig(arena="box", steps=40, seed=cfg["seed"])
    from dataclasses import asdict

    (parts / "run.json").write_text(json.dumps({**asdict(spec), "resumable": True}))
    tr = Trajectory.load(folder / "trajectory.npz")
    tr.head(20).save(parts / "part-0000000000.npz")
    return parts


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


@pytest.mark.parametrize("name", ["checkpoint.pkl", "checkpoint.npz"])
def test_a_crafted_pickle_as_a_checkpoint_runs_nothing(name, tmp_path, capsys):
    parts = _unfinished(tmp_path / "run")
    capsys.readouterr()
    proof = tmp_path / "pwned"
    if name.endswith(".pkl"):
        (parts / name).write_bytes(pickle.dumps((20, pickle.dumps(_Evil(proof)))))
    else:  # an npz whose meta is an object array: loading it would unpickle
        with open(parts / name, "wb") as f:
            np.savez(f, __meta__=np.array([_Evil(proof)], dtype=object))
    before = (parts / name).read_bytes()
    assert main([*RUN, "--out", str(tmp_path / "run"), "--resume"]) == 2
    line = _one_line(capsys)
    assert name in line and ("--overwrite" in line or "not a readable" in line)
    assert not proof.exists()
    assert (parts / name).read_bytes() == before  # left as it was


@pytest.mark.parametrize(
    "content",
    [b"", b"garbage", b"PK\x03\x04truncated", b"{}", bytes(range(256)) * 8],
    ids=["empty", "text", "truncated-zip", "json", "binary"],
)
def test_a_damaged_checkpoint_is_named_in_one_line(content, tmp_path, capsys):
    parts = _unfinished(tmp_path / "run")
    (parts / "checkpoint.npz").write_bytes(content)
    capsys.readouterr()
    assert main([*RUN, "--out", str(tmp_path / "run"), "--resume"]) == 2
    assert "checkpoint.npz" in _one_line(capsys)
    assert (parts / "checkpoint.npz").read_bytes() == content


def _state(cfg: EpisodeConfig, steps: int) -> tuple[object, object, Checkpoint]:
    from neurowalk.body.world import OneWorld

    _, body, ctrl = build(cfg)
    body_rng, ctrl_rng, _ = seeds(cfg)
    body.reset(body_rng)
    ctrl.reset(ctrl_rng)
    prev = None
    for _ in range(steps):
        body.apply(ctrl.act(body.observe()))
        prev = OneWorld(body).advance_keeping_previous()
    return body, ctrl, capture(steps, {"body": body, "controller": ctrl}, prev)


def test_a_checkpoint_round_trips_through_its_file_and_continues_the_run(tmp_path):
    cfg = EpisodeConfig(arena="cluttered", steps=60, seed=4, reflexes=True, backbone=True)
    body, ctrl, ckpt = _state(cfg, 30)
    ckpt.save(tmp_path / "c.npz")
    back = Checkpoint.load(tmp_path / "c.npz")
    assert back.step == 30 and back.values == json.loads(json.dumps(ckpt.values))
    assert back.arrays.keys() == ckpt.arrays.keys()
    _, body2, ctrl2 = build(cfg)
    body_rng, ctrl_rng, _ = seeds(cfg)
    body2.reset(body_rng)
    ctrl2.reset(ctrl_rng)
    restore(back, {"body": body2, "controller": ctrl2})
    for _ in range(20):  # the two go on as one
        a, b = ctrl.act(body.observe()), ctrl2.act(body2.observe())
        np.testing.assert_array_equal(a, b)
        body.apply(a), body2.apply(b)
        body.advance(), body2.advance()
    np.testing.assert_array_equal(body.data.qpos, body2.data.qpos)


def test_a_checkpoint_of_another_run_or_a_newer_format_is_refused(tmp_path):
    _, _, ckpt = _state(EpisodeConfig(arena="box", steps=5), 3)
    _, wheeled, ctrl = build(EpisodeConfig(arena="box", body="wheeled", steps=5))
    with pytest.raises(CheckpointError):
        restore(ckpt, {"body": wheeled, "controller": ctrl})
    ckpt.save(tmp_path / "c.npz")
    with np.load(tmp_path / "c.npz") as z:
        arrays = dict(z)
    meta = json.loads(bytes(arrays["__meta__"]).decode())
    meta["format"] = FORMAT + 1
    arrays["__meta__"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    np.savez(tmp_path / "newer.npz", **arrays)
    with pytest.raises(CheckpointError, match="newer neurowalk"):
        Checkpoint.load(tmp_path / "newer.npz")


def test_a_damaged_physics_state_is_caught_on_restore(tmp_path):
    cfg = EpisodeConfig(arena="box", steps=5)
    _, _, ckpt = _state(cfg, 3)
    ckpt.arrays["body/data#previous"][0] += 1.0  # the time one step before: no longer continues to the end state
    _, body, ctrl = build(cfg)
    with pytest.raises(CheckpointError, match="damaged"):
        restore(ckpt, {"body": body, "controller": ctrl})


def test_resume_without_a_checkpoint_starts_at_step_0_and_equals_a_whole_run(tmp_path, capsys):
    parts = _unfinished(tmp_path / "run")
    whole = Trajectory.load(tmp_path / "run" / "trajectory.npz")
    (tmp_path / "run" / "summary.json").unlink()
    (tmp_path / "run" / "trajectory.npz").unlink()
    capsys.readouterr()
    assert main([*RUN, "--out", str(tmp_path / "run"), "--resume"]) == 0
    assert "step 0" in capsys.readouterr().err
    again = Trajectory.load(tmp_path / "run" / "trajectory.npz")
    for f in ("t", "pose", "qpos", "outputs", "b", "q"):
        np.testing.assert_array_equal(getattr(again, f), getattr(whole, f))
    assert not parts.exists()


def test_a_finished_run_is_not_replaced_without_overwrite(tmp_path, capsys):
    out = tmp_path / "run"
    assert main([*RUN, "--out", str(out)]) == 0
    before = (out / "summary.json").read_bytes()
    capsys.readouterr()
    assert main([*RUN, "--seed", "3", "--out", str(out)]) == 2
    assert "finished run" in _one_line(capsys) and (out / "summary.json").read_bytes() == before
    assert main([*RUN, "--seed", "3", "--out", str(out), "--overwrite"]) == 0
    assert json.loads((out / "summary.json").read_text())["seed"] == 3


def test_a_folder_in_use_by_another_run_is_refused(tmp_path, capsys):
    from neurowalk.fileio import folder_lock

    out = tmp_path / "run"
    out.mkdir()
    with folder_lock(out):
        assert main([*RUN, "--out", str(out)]) == 2
        assert "in use" in _one_line(capsys)
    assert main([*RUN, "--out", str(out)]) == 0


def test_a_killed_runs_temp_files_do_not_stop_a_new_run(tmp_path):
    out = tmp_path / "run"
    parts = _unfinished(out)
    (parts / ".part-0000000020.npz.x1y2.npz").write_bytes(b"half")
    (out / ".trajectory.npz.abcd.npz").write_bytes(b"half")
    assert main([*RUN, "--out", str(out), "--overwrite"]) == 0
    assert not parts.exists() and not list(out.glob(".trajectory.npz.*"))
