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
