"""Headless video of a recorded run (needs EGL or OSMesa; .ci/run installs them)."""

import imageio_ffmpeg
import numpy as np

from neurowalk.render import render_video
from neurowalk.sim.episode import EpisodeConfig, build, run_episode


def test_video_renders_the_recorded_run(tmp_path):
    cfg = EpisodeConfig(controller="fixed", steer=(-1, 1), steps=40)
    ep = run_episode(cfg)
    _, body, _ = build(cfg)
    path = render_video(body.model, ep.trajectory.qpos, tmp_path / "video.mp4", width=160, height=120, every=2)
    frames = imageio_ffmpeg.read_frames(str(path))
    meta = next(frames)
    imgs = [np.frombuffer(f, np.uint8) for f in frames]
    assert meta["size"] == (160, 120) and len(imgs) == 20
    assert np.std(imgs[0].astype(float)) > 5  # a scene, not a blank frame
    assert not any(p.name.startswith(".") for p in tmp_path.iterdir())  # no temp file left


def test_video_without_gl_exits_2_before_the_run(tmp_path):
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["MUJOCO_GL"] = "glfw"  # needs a display: no GL here
    out = tmp_path / "run"
    cmd = [sys.executable, "-m", "neurowalk.cli", "run", "--steps", "100000", "--video", "--out", str(out)]
    r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    err = r.stderr.strip().splitlines()
    assert len(err) == 1 and "--video: no OpenGL" in err[0]
    assert not out.exists()  # refused before any work


def test_centred_snapshots_look_at_the_trunk_wherever_it_walked():
    """A centred frame of a row far from the start is the fixed view looking at that row's trunk, not the view at
    the start (MuJoCo's tracking camera lags between far-apart rows and can lose it)."""
    import mujoco

    from neurowalk.body.amosii_params import TRUNK_BODY
    from neurowalk.render import render_frames

    cfg = EpisodeConfig(controller="fixed", steer=(-1, -1), steps=10)
    _, body, _ = build(cfg)
    rows = np.repeat(body.data.qpos[None], 2, axis=0)
    rows[1, 0] += 4.0  # the same pose, 4 m ahead
    kw = {"width": 80, "height": 60, "distance": 1.4, "elevation": -50.0, "azimuth": 135.0}
    centred = render_frames(body.model, rows, centred=True, **kw)
    data = mujoco.MjData(body.model)
    data.qpos[:] = rows[1]
    mujoco.mj_kinematics(body.model, data)
    trunk = data.xpos[body.model.body(TRUNK_BODY).id].copy()
    view = {"lookat": trunk, "distance": 1.4, "azimuth": 135.0, "elevation": -50.0}
    fixed = render_frames(body.model, rows[1:], view=view, width=80, height=60)

    def diff(a: np.ndarray, b: np.ndarray) -> float:
        return float(np.abs(a.astype(int) - b).mean())

    assert diff(centred[1], fixed[0]) < 1.0  # the same view (within the lights' few grey levels)
    empty = render_frames(body.model, rows[1:], view={**view, "lookat": trunk - [4.0, 0, 0]}, width=80, height=60)
    assert diff(centred[1], empty[0]) > 3 * diff(centred[1], fixed[0])  # the view at the start: the robot is gone
