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
