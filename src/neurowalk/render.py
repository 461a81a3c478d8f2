"""Video of a recorded run (headless) and MuJoCo's interactive viewer.

Rendering replays recorded physics positions (``trajectory.qpos``) after the run, so it never
slows the simulation. Headless rendering needs ``MUJOCO_GL=egl`` (or ``osmesa``): :func:`use_headless_gl` sets it
before MuJoCo is imported where no display exists (the commands do), and :func:`offscreen_gl`, where rendering starts
in a process that imported MuJoCo already (a Gymnasium environment's ``render``), loads MuJoCo's GL context with it.
"""

from __future__ import annotations

import importlib
import os
import sys
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import imageio_ffmpeg
import numpy as np
from tqdm import tqdm

from neurowalk import profiling
from neurowalk.body.amosii_params import TRUNK_BODY
from neurowalk.fileio import atomic_write


def has_display() -> bool:
    """Whether an interactive window can be opened (X11/Wayland display, or macOS/Windows)."""
    return sys.platform in ("darwin", "win32") or bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def use_headless_gl() -> None:
    """Choose EGL for offscreen rendering unless a backend is already chosen (call before importing mujoco)."""
    if "mujoco" in sys.modules and "MUJOCO_GL" not in os.environ:
        return  # too late to choose; MuJoCo picked its default
    os.environ.setdefault("MUJOCO_GL", "egl")


def offscreen_gl() -> None:
    """Where offscreen rendering starts: with no display and no backend chosen (``MUJOCO_GL``), choose EGL. MuJoCo
    reads ``MUJOCO_GL`` as its GL context module loads (with ``import mujoco``): where it is loaded already, it is
    loaded again with EGL (it has made no context yet: there is no display to have made one on)."""
    if has_display() or "MUJOCO_GL" in os.environ:
        return
    os.environ["MUJOCO_GL"] = "egl"
    context = sys.modules.get("mujoco.rendering.classic.gl_context")
    if context is not None:
        importlib.reload(context)


def check_gl() -> str | None:
    """None if offscreen rendering works here, else one line saying why (call after :func:`use_headless_gl`)."""
    import mujoco  # here, not at the top: use_headless_gl must set MUJOCO_GL before MuJoCo is imported

    try:
        model = mujoco.MjModel.from_xml_string("<mujoco><worldbody><geom size='0.1'/></worldbody></mujoco>")
        with warnings.catch_warnings():  # a GL library's own warnings: the answer below says it in one line
            warnings.simplefilter("ignore")
            renderer = mujoco.Renderer(model, 8, 8)
    except Exception as e:  # every GL failure is the same answer: no rendering here
        backend = os.environ.get("MUJOCO_GL", "default")
        first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        return (
            f"no OpenGL for offscreen rendering (MUJOCO_GL={backend}: {first}); install EGL or OSMesa, "
            "e.g. `apt-get install libegl1` or `libosmesa6` with MUJOCO_GL=osmesa"
        )
    renderer.close()
    return None


def render_video(
    model: object,
    qpos: np.ndarray,
    path: str | Path,
    *,
    fps: float = 15.0,
    width: int = 640,
    height: int = 480,
    every: int = 2,
    distance: float = 1.3,
    shadows: bool = False,
    samples: int = 2,
    progress: bool = False,
) -> Path:
    """Render frames of recorded positions ``qpos`` (T, nq) to an mp4 at ``path`` (atomically).

    One renderer draws every frame and each frame goes to the encoder as soon as it is drawn (no frame list
    in memory).

    Args:
        model: the run's ``mujoco.MjModel``.
        qpos: recorded positions, one row per control step.
        fps: playback frame rate; with 10 Hz control and ``every`` = 2, 15 fps plays at 3x real time.
        every: render every ``every``-th row.
        distance: camera distance (m) from the trunk it tracks.
        shadows: draw shadows; off by default: with software GL (OSMesa, llvmpipe) they cost about 3/4 of a
            frame's time (``benchmarks/bench_render.py``).
        samples: multisampling (anti-aliasing) samples per pixel; 2 by default (MuJoCo's default 4 costs a
            fifth more time with software GL).
    """
    path, rows = Path(path), qpos[::every]
    frames = iter_frames(
        model, rows, width=width, height=height, distance=distance, elevation=-30.0, shadows=shadows, samples=samples
    )  # drawn one by one as the encoder takes them
    with profiling.part("video"):
        bar = tqdm(total=len(rows), unit="frame", desc="video", mininterval=0.5, disable=not progress)

        def write(tmp: str) -> None:
            writer = imageio_ffmpeg.write_frames(
                tmp, (width, height), fps=fps, quality=7, macro_block_size=8, output_params=["-preset", "veryfast"]
            )  # as small, 2x faster
            writer.send(None)
            try:
                for frame in frames:
                    writer.send(frame)
                    bar.update(1)
            finally:
                writer.close()
                bar.close()

        atomic_write(path, write)
    return path


def iter_frames(
    model: object,
    qpos: np.ndarray,
    *,
    width: int = 400,
    height: int = 300,
    distance: float = 1.2,
    azimuth: float = 135.0,
    elevation: float = -25.0,
    view: dict | None = None,
    centred: bool = False,
    shadows: bool = True,
    samples: int | None = None,
) -> Iterator[np.ndarray]:
    """Yield one (height, width, 3) uint8 frame per row of positions ``qpos`` (n, nq), drawn by one renderer.

    The camera tracks the trunk at ``distance`` (m), ``azimuth`` and ``elevation`` (deg); or, with ``view``
    ({"lookat": (3,) m, "distance", "azimuth", "elevation"}), it stays fixed there. MuJoCo's tracking camera
    follows the trunk smoothly, lagging behind between far-apart rows; ``centred`` looks at the trunk exactly in
    every frame instead (snapshots of a long run). Only kinematics are
    computed per frame (no dynamics, no collision detection). ``samples``: multisampling samples per pixel
    (default: the model's ``vis.quality.offsamples``, MuJoCo's 4).
    """
    import mujoco  # here, not at the top: use_headless_gl must set MUJOCO_GL before MuJoCo is imported

    data = mujoco.MjData(model)
    cam = mujoco.MjvCamera()
    trunk = model.body(TRUNK_BODY).id  # type: ignore[attr-defined]
    free = view is not None or centred  # else MuJoCo's camera tracking the trunk
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE if free else mujoco.mjtCamera.mjCAMERA_TRACKING
    cam.trackbodyid = -1 if free else trunk  # -1: MuJoCo's default, no body tracked
    if view is not None:
        cam.lookat[:] = view["lookat"]
        distance, azimuth, elevation = view["distance"], view["azimuth"], view["elevation"]
    cam.distance, cam.elevation, cam.azimuth = distance, elevation, azimuth
    quality = model.vis.quality  # type: ignore[attr-defined]
    own = quality.offsamples
    if samples is not None:
        quality.offsamples = samples  # read when the renderer is made; the model's own value is put back below
    try:
        offscreen_gl()  # no display and no backend chosen: EGL, chosen here where rendering starts
        renderer = mujoco.Renderer(model, height, width)
    finally:
        quality.offsamples = own
    try:
        for q in qpos:
            data.qpos[:] = q
            mujoco.mj_kinematics(model, data)
            mujoco.mj_camlight(model, data)
            if view is None and centred:
                cam.lookat[:] = data.xpos[trunk]
            renderer.update_scene(data, camera=cam)
            renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = shadows
            yield renderer.render()
    finally:
        renderer.close()


def view(model: object, data: object, step: object, control_hz: float = 10.0) -> None:
    """Open MuJoCo's passive viewer and call ``step()`` (one control step) in real time until it closes."""
    import mujoco.viewer  # here, not at the top: use_headless_gl must set MUJOCO_GL before MuJoCo is imported

    with mujoco.viewer.launch_passive(model, data) as v:
        period = 1.0 / control_hz
        while v.is_running():
            t0 = time.perf_counter()
            step()
            v.sync()
            time.sleep(max(0.0, period - (time.perf_counter() - t0)))


def render_frames(model: object, qpos: np.ndarray, **kwargs: Any) -> np.ndarray:
    """Render positions ``qpos`` (n, nq) as (n, height, width, 3) uint8; keywords as :func:`iter_frames`."""
    frames = list(iter_frames(model, qpos, **kwargs))
    if not frames:
        raise ValueError("render_frames: no positions to render (qpos has 0 rows)")
    return np.stack(frames)
