"""The commands of one closed-loop run: `run` (resumable, its final save shielded from signals) and `view`."""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from neurowalk.cli.common import UsageError, check_engine, engine_args, episode_args, episode_config, out_folder


def add_run_parsers(sub: argparse._SubParsersAction) -> None:
    """The `run` and `view` subcommands."""
    r = sub.add_parser("run", help="one closed-loop run: writes DIR/summary.json, trajectory.npz, run.png")
    episode_args(r)
    engine_args(r)
    r.add_argument("--out", type=Path, default=Path("out/run"), help="output folder (default out/run)")
    r.add_argument("--video", action="store_true", help="also render DIR/video.mp4 (headless)")
    r.add_argument("--quiet", action="store_true", help="no progress bar")
    r.add_argument("--overwrite", action="store_true",
                   help="run even where DIR holds the parts of an unfinished (killed) run, deleting them")  # fmt: skip
    r.add_argument("--resume", action="store_true",
                   help="go on with the unfinished physics run in DIR from its last checkpoint (every 10,000 steps; "
                        "its own settings are used, the others given here are ignored)")  # fmt: skip

    v = sub.add_parser("view", help="watch a closed-loop run live in MuJoCo's viewer (needs a display)")
    episode_args(v)


def cmd_run(args: argparse.Namespace) -> int:
    """`neurowalk run`: one closed-loop run into DIR (resumable where it is a physics run)."""
    if args.video and args.body != "amosii":
        raise UsageError(f"--video needs --body amosii (the {args.body!r} body has no 3-D state to render)")
    if args.video:
        from neurowalk.render import check_gl, use_headless_gl

        use_headless_gl()
        problem = check_gl()  # before the run, not after it
        if problem:
            raise UsageError(f"--video: {problem}")
    cfg = episode_config(args)
    check_engine(args)  # after the config's own checks: a bad body is named before any device is looked for
    from neurowalk.fileio import atomic_write, write_json
    from neurowalk.sim.episode import RunInterruptedError, build, run_episode
    from neurowalk.sim.trajectory import PartWriter

    out = out_folder(args.out)
    parts = PartWriter(out / "trajectory.parts")
    resume = None
    if args.resume:
        cfg, resume = _resume_point(parts)
    elif any(parts.folder.glob("part-*.npz")) and not args.overwrite:
        raise UsageError(f"{str(out)!r} holds the parts of an unfinished run ({parts.folder.name}/, e.g. a killed "
                         "one): --resume to go on with it, or --overwrite to start afresh")  # fmt: skip
    else:
        parts.remove()
        if cfg.body == "amosii" and cfg.engine == "mujoco":  # type: ignore[attr-defined]  # checkpointed
            parts.folder.mkdir()
            write_json(parts.folder / "run.json", {**dataclasses.asdict(cfg), "resumable": True})  # type: ignore[call-overload]
    import signal

    def _stop(signum: int, frame: object) -> None:
        raise KeyboardInterrupt  # a killed job (SIGTERM) keeps what it finished, like Ctrl-C

    signal.signal(signal.SIGTERM, _stop)
    interrupted = False
    try:
        ep = run_episode(
            cfg,
            progress=not args.quiet,
            sink=parts,
            keep_rows=False,  # memory bounded by the part size: the rows live in the parts
            resume=resume,  # type: ignore[arg-type]
            checkpoint=parts.write_checkpoint if cfg.body == "amosii" and cfg.engine == "mujoco" else None,
        )  # type: ignore[attr-defined]
    except RunInterruptedError as stop:
        ep, interrupted = stop.episode, True
    done = ep.summary["steps"]  # completed steps
    with signals_held():  # a signal now would lose the finished run: the save finishes first
        if done:
            parts.join(out / "trajectory.npz", done)
        write_json(out / "summary.json", ep.summary)
        resumable = interrupted and parts.folder.is_dir() and parts.read_checkpoint() is not None
        if not resumable:
            parts.remove()
        if not interrupted:
            from neurowalk.plotting import plot_run  # after the run: matplotlib's memory is not held through it

            fig = plot_run(ep.trajectory, ep.arena, ep.summary)
            atomic_write(out / "run.png", lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
        for stale in ("video.mp4", *(("run.png",) if interrupted else ())):  # an earlier run's, not this one's
            (out / stale).unlink(missing_ok=True)
    if interrupted:
        more = f"; `--resume` goes on from step {parts.read_checkpoint()[0]}" if resumable else ""
        print(f"neurowalk: interrupted: kept the {done} completed steps in {out}{more}", file=sys.stderr)
        return 130
    written = ["summary.json", "trajectory.npz", "run.png"]
    if args.video:
        from neurowalk.render import render_video

        _, body, _ = build(cfg)  # type: ignore[arg-type]
        try:
            import numpy as np

            with np.load(out / "trajectory.npz") as z:
                qpos = z["qpos"]
            render_video(body.model, qpos, out / "video.mp4", progress=not args.quiet)
        except KeyboardInterrupt:
            print(f"neurowalk: interrupted while rendering: the run is kept in {out}, without a video",
                  file=sys.stderr)  # fmt: skip
            return 130
        written.append("video.mp4")
    s = ep.summary
    resumed = f" (resumed at step {s['resumed_at_step']})" if "resumed_at_step" in s else ""
    print(
        f"{cfg.arena}/{cfg.controller}: {s['steps']} steps{resumed} in {s['wall_time_s']:.1f} s "  # type: ignore[attr-defined]
        f"({_factor(s['real_time_factor'])}x real time); moved {s['forward_displacement_m']:+.2f} m, "
        f"turned {s['heading_change_deg']:+.0f} deg; wrote {', '.join(str(out / w) for w in written)}"
    )
    return 0


def _resume_point(parts: Any) -> tuple[Any, Any]:
    """(config, Resume) of the unfinished run whose parts are in ``parts``; UsageError if there is none."""
    import json

    from neurowalk.sim.episode import EpisodeConfig, Resume

    where = str(parts.folder)
    saved = parts.read_checkpoint() if parts.folder.is_dir() else None
    if saved is None or not (parts.folder / "run.json").is_file():
        raise UsageError(f"--resume: no checkpoint in {where!r} (a physics run leaves one every 10,000 steps)")
    spec = json.loads((parts.folder / "run.json").read_text())
    spec.pop("resumable", None)
    if spec.get("steer") is not None:
        spec["steer"] = tuple(spec["steer"])
    step, state = saved
    if (held := parts.count()) < step:
        raise UsageError(f"--resume: the parts in {where!r} hold {held} steps, the checkpoint is at {step}")
    print(f"neurowalk: resuming the run in {where} at step {step} of {spec['steps']}", file=sys.stderr)
    return EpisodeConfig(**spec), Resume(step, state, parts.pieces())


@contextlib.contextmanager
def signals_held() -> Iterator[None]:
    """Ignore Ctrl-C and SIGTERM inside the block (the final save of a run), then restore the handlers."""
    import signal

    old = {sig: signal.signal(sig, signal.SIG_IGN) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)


def cmd_view(args: argparse.Namespace) -> int:
    """`neurowalk view`: the run live in MuJoCo's viewer."""
    from neurowalk.render import has_display, view

    cfg = episode_config(args)
    if args.body != "amosii":
        raise UsageError(f"view needs --body amosii, got {args.body!r}")
    if not has_display():
        print("neurowalk view: no display here (DISPLAY is not set); use `neurowalk run --video` for a headless video",
              file=sys.stderr)  # fmt: skip
        return 1
    from neurowalk.sim.episode import build, seeds

    _, body, ctrl = build(cfg)  # type: ignore[arg-type]
    body_rng, ctrl_rng, _ = seeds(cfg)  # type: ignore[arg-type]
    body.reset(body_rng)
    ctrl.reset(ctrl_rng)

    def step() -> None:
        body.apply(ctrl.act(body.observe()))
        body.advance()

    view(body.model, body.data, step, control_hz=body.control_hz)
    return 0


def _factor(x: float) -> str:
    """A real-time factor as the run line prints it: whole above 10, two figures below (0.23, 2.5)."""
    return f"{x:.0f}" if x >= 10 else f"{x:.2g}"
