"""Video rendering: frames per second of ``render_video`` as it is against shadows and 4x multisampling (old).

Renders the same recorded run (physics, ``box`` arena, plastic controller) into an mp4 at 640 x 480 with each
setting, interleaved, ``--repeats`` times; the whole path is timed (kinematics, scene, GL, encoding). With
software GL (OSMesa, Mesa's llvmpipe behind EGL) shadow mapping costs most of a frame and 4 samples per pixel a
fifth more than 2. Reported: median frames
per second of each and their ratio, measured in the same run, for the GL backend given (``MUJOCO_GL``).

Run: ``MUJOCO_GL=egl python benchmarks/bench_render.py [--frames 200] [--repeats 3] [--out out/bench]``;
writes ``render-<backend>.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import tempfile
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

from neurowalk.render import render_video
from neurowalk.sim.episode import EpisodeConfig, build, run_episode

SETTINGS = {"shadows, 4 samples (old default)": {"shadows": True, "samples": 4}, "no shadows, 2 samples (default)": {}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    cfg = EpisodeConfig(arena="box", steps=args.frames, seed=0)
    qpos = run_episode(cfg).trajectory.qpos
    _, body, _ = build(cfg)
    times: dict[str, list[float]] = {k: [] for k in SETTINGS}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(args.repeats):
            for name, kw in SETTINGS.items():
                t0 = time.perf_counter()
                render_video(body.model, qpos, Path(tmp) / "v.mp4", every=1, **kw)
                times[name].append(time.perf_counter() - t0)
    fps = {k: args.frames / statistics.median(v) for k, v in times.items()}
    old, new = fps.values()
    backend = os.environ["MUJOCO_GL"]
    result = {"backend": backend, "frames": args.frames, "size": [640, 480], "repeats": args.repeats,
              "frames_per_s": fps, "speedup": new / old, "cores": os.cpu_count()}  # fmt: skip
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / f"render-{backend}.json").write_text(json.dumps(result, indent=2) + "\n")
    for k, v in fps.items():
        print(f"{backend}: {k}: {v:.1f} frames/s")
    print(f"{backend}: speed-up {new / old:.2f}x")


if __name__ == "__main__":
    main()
