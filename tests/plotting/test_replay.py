"""A run's 3-D replay rebuilt from its folder: the parts move as the run did, the rays start at the sensors, and a
folder that is not a run (or a damaged one) is named in one clear error."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from neurowalk.plotting.meshes import box_mesh, capsule_mesh, cylinder_mesh, ellipsoid_mesh, merge
from neurowalk.plotting.replay import RunFolderError, load_replay


@pytest.fixture(scope="module")
def physics_run(run_folder) -> Path:
    return run_folder("--arena", "box", "--steps", "200")


@pytest.fixture(scope="module")
def surrogate_run(run_folder) -> Path:
    return run_folder("--arena", "narrow-passage", "--body", "surrogate", "--steps", "400")


def _closed(faces: np.ndarray) -> bool:
    """Every edge of the mesh is shared by exactly two faces, once each way (a closed, consistently wound surface)."""
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    forward = {tuple(e) for e in edges}
    return len(forward) == len(edges) and all((b, a) in forward for a, b in forward)


def test_shapes_are_closed_and_have_their_sizes():
    for mesh, half in (
        (box_mesh(0.1, 0.2, 0.3), (0.1, 0.2, 0.3)),
        (capsule_mesh(0.05, 0.2), (0.05, 0.05, 0.25)),
        (ellipsoid_mesh(0.1, 0.2, 0.3), (0.1, 0.2, 0.3)),
        (cylinder_mesh(0.1, 0.02), (0.1, 0.1, 0.02)),
    ):
        assert np.allclose(np.abs(mesh.vertices).max(axis=0), half, atol=1e-6)
        assert _closed(mesh.faces)
    both = merge([box_mesh(1, 1, 1), box_mesh(1, 1, 1, centre=(5, 0, 0))])
    assert len(both.vertices) == 16 and both.faces.max() == 15 and _closed(both.faces)


def test_a_physics_run_replays_as_it_walked(physics_run: Path):
    r = load_replay(physics_run)
    summary = json.loads((physics_run / "summary.json").read_text())
    assert r.steps == summary["steps"] and len(r.frames) == r.steps
    assert r.fixed and r.parts  # the arena's box and walls; the robot's bodies
    assert r.pos.shape == (r.steps, len(r.parts), 3) and np.allclose(np.linalg.norm(r.quat, axis=2), 1.0)
    # the robot's parts go where the trunk went: the part nearest the trunk stays within the robot's size of it
    trunk = r.path[r.frames]
    nearest = np.min(np.linalg.norm(r.pos - trunk[:, None, :], axis=2), axis=1)
    assert nearest.max() < 0.1
    assert np.linalg.norm(r.path[-1, :2] - r.path[0, :2]) > 0.05  # it walked
    # the rays start at the robot's front, about its body length from the trunk, and are at most the range long
    start = np.linalg.norm(r.ray_from[:, :, :2] - trunk[:, None, :2], axis=2)
    assert start.min() > 0.05 and start.max() < 0.5
    length = np.linalg.norm(r.ray_to - r.ray_from, axis=2)
    assert np.all(length > 0) and np.all(length <= 0.4 + 1e-9)


def test_a_surrogate_run_replays_on_its_pose(surrogate_run: Path):
    r = load_replay(surrogate_run)
    assert len(r.parts) == 1 and len(r.fixed) > 0  # its footprint; the passage's walls
    pose = np.load(surrogate_run / "trajectory.npz", allow_pickle=False)["pose"]
    assert np.allclose(r.pos[:, 0, :2], pose[r.frames, :2])
    yaw = 2 * np.arctan2(r.quat[:, 0, 3], r.quat[:, 0, 0])
    assert np.allclose(np.angle(np.exp(1j * (yaw - pose[r.frames, 2]))), 0, atol=1e-9)


def test_a_long_run_is_replayed_on_fewer_frames(physics_run: Path):
    r = load_replay(physics_run, max_frames=30)
    assert len(r.frames) <= 30 and r.frames[0] == 0 and r.steps == 200 and len(r.inputs) == 200
    assert r.frame_of_step(0) == 0 and r.frames[r.frame_of_step(199)] <= 199 < r.frames[r.frame_of_step(199)] + 7


def test_bad_folders_are_named(tmp_path: Path, physics_run: Path):
    with pytest.raises(RunFolderError, match="is not a folder"):
        load_replay(tmp_path / "nothing")
    with pytest.raises(RunFolderError, match=r"needs summary\.json and trajectory\.npz"):
        load_replay(tmp_path)
    damaged = tmp_path / "damaged"
    shutil.copytree(physics_run, damaged)
    data = (damaged / "trajectory.npz").read_bytes()
    (damaged / "trajectory.npz").write_bytes(data[: len(data) // 2])
    with pytest.raises(RunFolderError, match="damaged"):
        load_replay(damaged)
    (damaged / "summary.json").write_text("{")
    with pytest.raises(RunFolderError, match="not a readable summary"):
        load_replay(damaged)
    other = tmp_path / "other"
    shutil.copytree(physics_run, other)
    summary = json.loads((other / "summary.json").read_text())
    (other / "summary.json").write_text(json.dumps({**summary, "body": "wheeled"}))
    with pytest.raises(RunFolderError, match="does not fit the wheeled model"):
        load_replay(other)
