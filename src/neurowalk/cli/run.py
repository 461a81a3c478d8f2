"""The command of one closed-loop run: `run` (resumable, its final save shielded from signals)."""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from neurowalk.cli.common import (
    UsageError,
    check_engine,
    engine_args,
    episode_args,
    episode_config,
    failed,
    machine_memory,
    out_folder,
    stop_line,
)
from neurowalk.cli.view import check_web, keep_serving, live_page, web_args
from neurowalk.fileio import FolderBusyError, atomic_write, folder_lock, stale_temp_files, write_error, write_json
from neurowalk.runners.stopping import interrupted as interrupted_by_signal
from neurowalk.runners.stopping import stop_requested, stop_status

if TYPE_CHECKING:
    from neurowalk.plotting.live import LivePage
    from neurowalk.sim.engine_interface import EngineOptions, Resume
    from neurowalk.sim.episode import Episode, EpisodeConfig
    from neurowalk.sim.trajectory import PartWriter


def add_run_parsers(sub: argparse._SubParsersAction) -> None:
    """The `run` subcommand."""
    r = sub.add_parser("run", help="one closed-loop run: writes DIR/summary.json, trajectory.npz, run.png")
    episode_args(r)
    engine_args(r)
    r.add_argument("--out", type=Path, default=Path("out/run"), help="output folder (default out/run)")
    r.add_argument("--video", action="store_true", help="also render DIR/video.mp4 (headless)")
    r.add_argument(
        "--web",
        action="store_true",
        help="show the run in the browser as it runs, on `neurowalk view`'s page (the web extra); the page stays "
        "after the run, until Ctrl-C",
    )
    web_args(r)
    r.add_argument("--quiet", action="store_true", help="no progress bar, nor the note while the kernels compile")
    r.add_argument(
        "--overwrite",
        action="store_true",
        help="replace the run in DIR, finished or not (a run into a folder that holds one is refused)",
    )
    r.add_argument(
        "--resume",
        action="store_true",
        help="go on with the unfinished run in DIR from its last checkpoint (MuJoCo bodies: every 10,000 "
        "steps), or from step 0 where it has none; its own settings are used, those given here are "
        "ignored",
    )


def cmd_run(args: argparse.Namespace) -> int:
    """`neurowalk run`: one closed-loop run into DIR (resumable where it is a physics run).

    The first SIGINT or SIGTERM stops it (exit 130, or 143 for SIGTERM): the completed steps are written to DIR, and
    one line says what `--resume` goes on from.
    """
    if args.video:
        from neurowalk.render import use_headless_gl

        use_headless_gl()  # before MuJoCo is imported (the body registry imports it)
    from neurowalk.body.registry import bodies_where

    if args.video and args.body in bodies_where(lambda b: not b.physics):  # an unknown body: the config's check
        raise UsageError(f"--video needs a MuJoCo body; {args.body!r} is planar (no 3-D model to render)")
    if args.resume and args.overwrite:
        raise UsageError("--resume and --overwrite exclude each other: go on with the run in DIR, or start afresh")
    if args.video:
        from neurowalk.render import check_gl

        if problem := check_gl():  # before the run, not after it
            raise UsageError(f"--video: {problem}")
    cfg = episode_config(args)
    options = check_engine(args)  # after the config's own checks: a bad body is named before a device is looked for
    _check_memory(cfg.steps)
    if args.web:
        check_web(args)
    from neurowalk.sim.engines import engine_for
    from neurowalk.sim.trajectory import PartWriter

    out = out_folder(args.out)
    try:
        lock = folder_lock(out, "run")
    except (FolderBusyError, OSError) as e:
        why = f"--out {e}" if isinstance(e, FolderBusyError) else f"--out {str(out)!r}: {e.strerror}"
        raise UsageError(why) from None
    with lock:
        resumable = engine_for(cfg).resumable  # its runs leave a checkpoint every part (the CPU loop's)
        parts = PartWriter(out / "trajectory.parts")
        cfg, resume, resumable = _start(args, cfg, out, parts, resumable)
        page = live_page(cfg, parts, args) if args.web else None  # --web: the rows go to the page, then the parts
        try:
            return _run_and_save(args, cfg, out, parts, resume, options, page, resumable)
        finally:
            if page is not None:
                page.close()


#: Memory a streamed run holds per control step (the summary's columns), and what it needs besides (Python, MuJoCo,
#: numba's kernels, one part and the picture): ``docs/benchmarks/memory.json``.
RUN_BYTES_PER_STEP, RUN_BASE_BYTES = 41, 300 * 10**6


def _check_memory(steps: int) -> None:
    """UsageError, before any work, where a run of ``steps`` steps needs more memory than this machine has."""
    need, have = RUN_BASE_BYTES + RUN_BYTES_PER_STEP * steps, machine_memory()
    if have is not None and need > have:
        raise UsageError(
            f"--steps {steps:,}: a run keeps {RUN_BYTES_PER_STEP} bytes a step in memory, "
            f"{need / 1e9:,.1f} GB in all, more than this machine's {have / 1e9:,.1f} GB"
        )


def _start(
    args: argparse.Namespace, cfg: EpisodeConfig, out: Path, parts: PartWriter, resumable: bool
) -> tuple[EpisodeConfig, Resume | None, bool]:
    """(config, Resume or None, resumable: its runs leave checkpoints) of the run to make in ``out`` (``cfg`` and
    ``resumable``: the arguments' run; with ``--resume``, the folder's own); refuses to replace a run without
    ``--overwrite``."""
    unfinished = parts.folder.is_dir() and any(parts.folder.iterdir())
    finished = not unfinished and (out / "summary.json").is_file()
    if args.resume and unfinished:
        from neurowalk.sim.engines import engine_for

        cfg, resume = _resume_point(parts)
        resumable = engine_for(cfg).resumable
        if resume is not None:
            return cfg, resume, resumable
    elif args.resume and finished:
        raise UsageError(f"--resume: {str(out)!r} holds a finished run (summary.json); --overwrite runs it again")
    elif args.resume:
        print(f"neurowalk: --resume: no unfinished run in {out}: starting at step 0", file=sys.stderr)
    elif unfinished and not args.overwrite:
        raise UsageError(
            f"{str(out)!r} holds an unfinished run ({parts.folder.name}/, e.g. a stopped or killed "
            "one): --resume to go on with it, or --overwrite to start afresh"
        )
    elif finished and not args.overwrite:
        raise UsageError(
            f"{str(out)!r} holds a finished run (summary.json): --overwrite to replace it, or another --out"
        )
    _clear(out, parts)
    parts.folder.mkdir()
    write_json(parts.folder / "run.json", {**cfg.spec(), "resumable": resumable})
    return cfg, None, resumable


def _clear(out: Path, parts: PartWriter) -> None:
    """Remove an earlier run's files from ``out`` (the new run writes its own), temp files of a killed one too."""
    parts.remove()
    for name in ("summary.json", "trajectory.npz", "run.png", "video.mp4"):
        (out / name).unlink(missing_ok=True)
    for stale in stale_temp_files(out):
        stale.unlink(missing_ok=True)


def _run_and_save(
    args: argparse.Namespace,
    cfg: EpisodeConfig,
    out: Path,
    parts: PartWriter,
    resume: Resume | None,
    options: EngineOptions,
    page: LivePage | None,
    resumable: bool,
) -> int:
    """Run ``cfg`` with its rows streamed into ``parts`` (or to ``page``, with ``--web``, which passes them on; a
    checkpoint with every part where ``resumable``), then write DIR's files; the exit status."""
    from neurowalk.sim.episode import RunInterruptedError, Streaming, run_episode

    interrupted = False
    try:
        try:
            ep = run_episode(
                cfg,
                options=dataclasses.replace(options, progress=not args.quiet),
                stream=Streaming(
                    sink=page.live if page is not None else parts,
                    **({"chunk": page.live.chunk} if page is not None else {}),
                    keep_rows=False,
                    resume=resume,
                    checkpoint=parts.write_checkpoint if resumable else None,
                    stop=stop_requested,  # a stop whose KeyboardInterrupt a library swallowed (e.g. amid an import)
                ),
            )
        except RunInterruptedError as stop:
            ep, interrupted = stop.episode, True
        with signals_held():  # a signal now would lose the finished run: the save finishes first
            _save(out, parts, ep, interrupted)
            then = _keep_for_resume(parts, resumable) if interrupted else ""
    except OSError as e:
        return failed(
            f"neurowalk: {write_error(e)}: {_kept(parts)}; free space (or fix the folder) and run again with --resume"
        )
    except Exception as e:  # a failure inside the loop: what it finished is in the parts, and the line says so
        if interrupted_by_signal(e):  # e.g. an ImportError out of a C extension's import that a stop cut short
            raise KeyboardInterrupt from None
        why = str(e).splitlines()[0] if str(e) else ""
        return failed(
            f"neurowalk: the run failed ({type(e).__name__}: {why}): {_kept(parts)}; `--resume` runs it again "
            "from its last checkpoint"
        )
    done = ep.summary["steps"]
    if interrupted:
        files = "summary.json, trajectory.npz, run.png" if done else "summary.json"
        return stop_line(f"neurowalk: interrupted: kept the {done} completed steps in {out} ({files}); {then}")
    written = ["summary.json", "trajectory.npz", "run.png"]
    if args.video:
        if not _video(cfg, out, args.quiet):
            return stop_status()
        written.append("video.mp4")
    s = ep.summary
    resumed = f" (resumed at step {s['resumed_at_step']})" if "resumed_at_step" in s else ""
    print(
        f"{cfg.arena}/{cfg.controller}: {s['steps']} steps{resumed} in {s['wall_time_s']:.1f} s "
        f"({_factor(s['real_time_factor'])}x real time); {outcome_words(ep)}"
        f"{moved_words(s)}, turned {s['heading_change_deg']:+.0f} deg; wrote {', '.join(str(out / w) for w in written)}"
    )
    if page is not None:
        keep_serving(page, args)
    return 0


def moved_words(s: dict[str, Any]) -> str:
    """How far a run's trunk went, in words: ``"ended 1.16 m from its start (+0.69 m ahead), path 2.08 m"`` (the
    straight line, its part along the start heading, the length of the path)."""
    return (
        f"ended {s['net_displacement_m']:.2f} m from its start ({s['forward_displacement_m']:+.2f} m ahead), "
        f"path {s['path_length_m']:.2f} m"
    )


def outcome_words(ep: Episode) -> str:
    """The run's outcome in words, for an arena with an exit region (else ""): ``"climbed at 136.6 s; "`` or
    ``"did not climb; "`` on a step, ``"escaped at 52.3 s; "`` or ``"did not escape (trapped); "`` in a dead end."""
    arena, s = ep.arena, ep.summary
    if arena.exit_region is None:
        return ""
    reached, missed = arena.exit_words
    if s["exit_step"] is not None:
        return f"{reached} at {s['exit_step'] / s['control_hz']:.1f} s; "
    return f"{missed}{' (trapped)' if s['trapped'] else ''}; "


def _kept(parts: PartWriter) -> str:
    """The steps on disk in ``parts``, in words."""
    held = parts.count() if parts.folder.is_dir() else 0
    return f"steps 0-{held - 1:,} kept in {parts.folder}" if held else "no steps kept"


def _save(out: Path, parts: PartWriter, ep: Episode, interrupted: bool) -> None:
    """Write the run's files, all of the same steps: trajectory.npz, run.png, then summary.json (last)."""
    from neurowalk.plotting import look, plot_run  # after the run: matplotlib's memory is not held through it

    done = ep.summary["steps"]
    if done:
        parts.join(out / "trajectory.npz", done)
        fig = plot_run(ep.trajectory, ep.arena, ep.summary)
        with look():  # saved in neurowalk's look: tick labels are laid out as it is drawn
            atomic_write(out / "run.png", lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    write_json(out / "summary.json", ep.summary)
    if not interrupted:
        parts.remove()  # the run is whole in trajectory.npz


def _keep_for_resume(parts: PartWriter, resumable: bool) -> str:
    """Keep in ``parts`` only what `--resume` needs of a stopped run whose rows are in trajectory.npz now (the rows
    are not kept twice); what a rerun goes on from, in words.

    With a checkpoint: it, and the parts of the steps before it (a resumed run reads them back). Without one (a run
    stopped before its first, or of an engine that keeps none): the run's settings, ``run.json``, only.
    """
    import shutil

    from neurowalk.sim.checkpoint import CheckpointError

    try:
        ckpt = parts.read_checkpoint()
    except CheckpointError:  # unreadable: `--resume` could not go on from it either
        ckpt = None
    if ckpt is not None:
        parts.drop_from(ckpt.step)  # rows after the checkpoint are run again
        return f"`--resume` goes on from step {ckpt.step} (its checkpoint and rows kept in {parts.folder})"
    for p in parts.folder.iterdir():
        if p.name == "run.json":
            continue
        if p.is_dir():
            shutil.rmtree(p)
        else:
            p.unlink()
    yet, settings = " yet" if resumable else "", parts.folder / "run.json"
    return f"no checkpoint{yet}: `--resume` starts it again from step 0 (its settings kept in {settings})"


def _video(cfg: EpisodeConfig, out: Path, quiet: bool) -> bool:
    """Render DIR/video.mp4 from DIR/trajectory.npz; False if interrupted (the run is kept without it)."""
    import numpy as np

    from neurowalk.render import render_video
    from neurowalk.sim.episode import build

    _, body, _ = build(cfg)
    try:
        with np.load(out / "trajectory.npz", allow_pickle=False) as z:
            qpos = z["qpos"]
        render_video(body.model, qpos, out / "video.mp4", progress=not quiet)
    except KeyboardInterrupt:
        print(f"neurowalk: interrupted while rendering: the run is kept in {out}, without a video", file=sys.stderr)
        return False
    return True


def _resume_point(parts: PartWriter) -> tuple[EpisodeConfig, Resume | None]:
    """(config, Resume) of the unfinished run in ``parts``; (config, None) where it has no checkpoint yet."""
    import json

    from neurowalk.sim.checkpoint import CheckpointError
    from neurowalk.sim.episode import EpisodeConfig, Resume

    where, spec_path = str(parts.folder), parts.folder / "run.json"
    try:
        spec = json.loads(spec_path.read_text())
        spec.pop("resumable", None)
        cfg = EpisodeConfig.from_spec(spec)
    except FileNotFoundError:
        raise UsageError(
            f"--resume: {where!r} holds parts but no run.json (not a run neurowalk can go on "
            "with); --overwrite to start afresh"
        ) from None
    except (OSError, ValueError, TypeError, AttributeError) as e:
        raise UsageError(
            f"--resume: {str(spec_path)!r} is damaged ({type(e).__name__}); --overwrite to start afresh"
        ) from None
    try:
        ckpt = parts.read_checkpoint()
    except CheckpointError as e:
        raise UsageError(f"--resume: {e}") from None
    if ckpt is None:
        print(f"neurowalk: no checkpoint yet in {where}: starting the run again at step 0", file=sys.stderr)
        return cfg, None
    if (held := parts.count_before(ckpt.step)) < ckpt.step:
        raise UsageError(f"--resume: the parts in {where!r} hold {held} steps, the checkpoint is at {ckpt.step}")
    parts.drop_from(ckpt.step)  # rows after the checkpoint are run again
    print(f"neurowalk: resuming the run in {where} at step {ckpt.step} of {cfg.steps}", file=sys.stderr)
    return cfg, Resume(ckpt, parts.pieces())


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


def _factor(x: float) -> str:
    """A real-time factor as the run line prints it: whole above 10, two figures below (0.23, 2.5)."""
    return f"{x:.0f}" if x >= 10 else f"{x:.2g}"
