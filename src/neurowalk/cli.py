"""Command line: ``neurowalk figure NAME --out DIR`` and friends. Thin: parses, calls the library.

Bad input exits with status 2 and one line on stderr naming the offending value.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from neurowalk import __version__


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


class _Parser(argparse.ArgumentParser):
    help_tail: Callable[[], str] | None = None  # more help, computed only when help is asked for

    def error(self, message: str) -> None:  # one clear line instead of usage + message
        raise UsageError(message)

    def format_help(self) -> str:
        return super().format_help() + (self.help_tail() if self.help_tail else "")


def out_folder(path: Path, flag: str = "--out", given: Path | None = None) -> Path:
    """Make the output folder ``path`` (and its parents); UsageError naming it if it is a file or cannot be written.

    ``given``: the path the user gave, named in the message (default ``path``; e.g. a file inside the folder).
    """
    import tempfile

    shown = f"{flag} {str(given if given is not None else path)!r}"
    try:
        if path.exists() and not path.is_dir():
            raise UsageError(f"{shown}: {str(path)!r} is a file, not a folder")
        path.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise UsageError(f"{shown}: cannot make the folder {str(path)!r} ({e.strerror})") from None
    try:  # a real write, not os.access (which lets root 'write' where nothing can be written, e.g. /proc)
        with tempfile.TemporaryFile(dir=path):
            pass
    except OSError as e:
        raise UsageError(f"{shown}: the folder {str(path)!r} is not writable ({e.strerror})") from None
    return path


def out_file(path: Path, flag: str = "--out") -> Path:
    """Check that the output file ``path`` can be written (its folder made); UsageError naming it otherwise."""
    try:
        if path.is_dir():
            raise UsageError(f"{flag} {str(path)!r} is a folder; give a file name")
        if len(path.name.encode()) > 255:
            raise UsageError(f"{flag} {str(path)!r}: file name too long")
    except OSError as e:
        raise UsageError(f"{flag} {str(path)!r}: {e.strerror}") from None
    out_folder(path.parent if str(path.parent) else Path("."), flag, given=path)
    return path


def figure_listing() -> str:
    """The figures, one per line: name and one-line description, aligned."""
    from neurowalk.experiments import FIGURES

    width = max(len(n) for n in FIGURES) + 2
    return "\n".join(f"{name:<{width}}{exp.title}" for name, exp in sorted(FIGURES.items()))


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="neurowalk", description="Adaptive neural control of the hexapod AMOSII (Grinke et al. 2015).")
    p.add_argument("--version", action="version", version=f"neurowalk {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    f = sub.add_parser("figure", help="reproduce a paper figure: writes DIR/NAME.png and DIR/NAME.json")
    f.help_tail = lambda: "\nfigures:\n" + "".join(f"  {line}\n" for line in figure_listing().splitlines())
    f.add_argument("name", help="figure name (see `neurowalk figure list`)")
    f.add_argument("--out", type=Path, default=None, help="output folder (default: out/NAME)")
    f.add_argument("--quick", action="store_true", help="shorter runs, coarser grids")
    f.add_argument("--seed", type=int, default=0, help="seed of every random draw (default 0)")
    f.add_argument(
        "--seeds", type=int, default=None, help="number of seeds per condition (figures with outcome tables)"
    )
    f.add_argument("--replot", action="store_true", help="redraw from DIR/NAME.json and .npz without rerunning")
    f.add_argument("--body", default=None, help="amosii | surrogate (figures that run on either; default per figure)")
    climb = "leg reflexes and backbone control on (fig3 fig5 escape-map table2; default out: out/NAME-climb)"
    f.add_argument("--climb", action="store_true", help=climb)
    _variant_args(f)
    f.add_argument("--gait", default=None, help="gait of the physics figures that take one (fig3 fig5 escape-map)")
    f.add_argument("--video", action="store_true", help="also write the example runs' videos (fig8, fig9)")
    f.add_argument("--arena-opt", action="append", default=[], metavar="size=M",
                   help="box side of the random environments (table2, fig6; default 1 m, the authors')")  # fmt: skip

    r = sub.add_parser("run", help="one closed-loop run: writes DIR/summary.json, trajectory.npz, run.png")
    _episode_args(r)
    r.add_argument("--out", type=Path, default=Path("out/run"), help="output folder (default out/run)")
    r.add_argument("--video", action="store_true", help="also render DIR/video.mp4 (headless)")
    r.add_argument("--quiet", action="store_true", help="no progress bar")
    r.add_argument("--overwrite", action="store_true",
                   help="run even where DIR holds the parts of an unfinished (killed) run, deleting them")  # fmt: skip
    r.add_argument("--resume", action="store_true",
                   help="go on with the unfinished physics run in DIR from its last checkpoint (every 10,000 steps; "
                        "its own settings are used, the others given here are ignored)")  # fmt: skip

    v = sub.add_parser("view", help="watch a closed-loop run live in MuJoCo's viewer (needs a display)")
    _episode_args(v)

    c = sub.add_parser("calibrate", help="measure the physics robot for the planar surrogate (writes a JSON file)")
    c.add_argument("--out", type=Path, default=Path("out/calibration/calibration.json"), help="file to write")
    c.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    c.add_argument("--quick", action="store_true", help="coarse grid (for a smoke test; not for shipping)")

    b = sub.add_parser("bench", help="measure the performance figures side by side: writes DIR/bench.json")
    b.add_argument("--out", type=Path, default=Path("out/bench"), help="output folder (default out/bench)")
    b.add_argument("--quick", action="store_true", help="short measurements (a smoke test)")
    b.add_argument("--workers", type=int, default=None, help="processes / threads (default: the cores, up to 8)")

    sub.add_parser("arenas", help="list the arenas and their options")
    e = sub.add_parser("export-model", help="write the robot (and an arena) as a self-contained MJCF file")
    e.add_argument("--out", type=Path, required=True, help="MJCF file to write")
    e.add_argument("--arena", default="open", help="arena to include (default open)")
    e.add_argument("--arena-opt", action="append", default=[], metavar="KEY=VALUE", help="arena option")
    _sweep_parser(sub)
    _optimize_parser(sub)
    return p


def _sweep_parser(sub: argparse._SubParsersAction) -> None:
    s = sub.add_parser("sweep", help="many runs (a grid, or specs from a file), resumable, into DIR/results.sqlite")
    s.add_argument("--arena", default=None, metavar="NAME[,NAME...]", help="arenas (default open)")
    s.add_argument("--controller", default=None, metavar="NAME[,NAME...]", help="controllers (default plastic)")
    s.add_argument("--body", default=None, metavar="NAME[,NAME...]", help="bodies (default amosii)")
    s.add_argument("--seeds", type=int, default=None, help="seeds per condition (default 1)")
    s.add_argument("--seed-start", type=int, default=None, help="first seed (default 0): seeds S, S+1, ...")
    s.add_argument("--steps", type=int, default=None, help="control steps per run (default 1000)")
    s.add_argument("--arena-opt", action="append", default=[], metavar="KEY=V1[,V2...]",
                   help="arena option; a comma list adds a grid axis (repeatable)")  # fmt: skip
    s.add_argument("--specs", type=Path, default=None, metavar="FILE.jsonl",
                   help="one run spec (JSON object of EpisodeConfig fields) per line, instead of the grid")  # fmt: skip
    s.add_argument("--backend", choices=("local", "ray"), default="local", help="local process pool or Ray")
    s.add_argument("--address", default=None, help="Ray cluster to join (backend ray; default: a local instance)")
    s.add_argument("--workers", type=int, default=2, help="processes, or CPUs of a local Ray instance (default 2)")
    s.add_argument("--retries", type=int, default=0, metavar="N",
                   help="run a job whose worker died up to N more times (default 0: store it as failed)")  # fmt: skip
    s.add_argument("--gait", default=None, metavar="NAME[,NAME...]", help="gaits (default wave)")
    s.add_argument("--out", type=Path, required=True, help="output folder (the store; resumes what is there)")
    s.add_argument("--export", choices=("parquet", "csv"), default=None, help="also write DIR/results.parquet|csv")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    _variant_args(s, many=True)


def _episode_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--arena", default="open", help="arena name (see `neurowalk arenas`)")
    p.add_argument("--arena-opt", action="append", default=[], metavar="KEY=VALUE", help="arena option, repeatable")
    p.add_argument("--controller", default="plastic", help="plastic | static | braitenberg | fixed")
    p.add_argument("--steer", default=None, metavar="O1,O2", help="steering of controller 'fixed', e.g. -1,-1")
    p.add_argument("--body", default="amosii", help="amosii (MuJoCo physics) | surrogate (planar, calibrated)")
    p.add_argument("--steps", type=int, default=1000, help="control steps (10 Hz: 1000 = 100 s)")
    p.add_argument("--seed", type=int, default=0, help="seed of every random draw")
    p.add_argument("--reflexes", action="store_true", help="local leg control: searching and elevation reflexes")
    p.add_argument("--backbone", action="store_true", help="backbone joint control and climbable-step detection")
    p.add_argument("--climb", action="store_true", help="both --reflexes and --backbone (climbing)")
    _variant_args(p)
    p.add_argument(
        "--gait", default="wave", help="slow-wave | wave (default) | slow-tetrapod | tetrapod | tripod | fast"
    )


def _variant_args(p: argparse.ArgumentParser, many: bool = False) -> None:
    names = "paper | original | tuned"
    p.add_argument("--variant", default=None, metavar="NAME[,NAME...]" if many else "NAME",
                   help=f"the network: {names} (default paper: Eq. 1-6 as printed; original: the authors' code; "
                   "see docs/paper-vs-code.md)")  # fmt: skip
    p.add_argument("--params", type=Path, default=None, metavar="FILE.json",
                   help="SensoryParams fields on top of the variant, e.g. an `optimize` best.json")  # fmt: skip


def _variant(args: argparse.Namespace) -> tuple[str, dict | None]:
    """(variant, params overrides) of --variant/--params; a params file names its own base variant."""
    from neurowalk.neural.variants import get_variant, read_params_file

    params = None
    variant = args.variant
    if variant is not None and not variant.strip():
        raise UsageError(f"--variant expects a name (e.g. paper, original), got {variant!r}")
    try:
        if args.params is not None:
            data = read_params_file(args.params)
            params = data["params"]
            variant = variant or data["variant"]
        variant = variant or "paper"
        get_variant(variant, params)
    except ValueError as e:
        raise UsageError(str(e)) from None
    return variant, params


def _arena_opts(items: list[str]) -> dict[str, str]:
    opts = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise UsageError(f"--arena-opt expects KEY=VALUE, got {item!r}")
        opts[key] = value
    return opts


def _steer(text: str | None) -> tuple[float, float] | None:
    if text is None:
        return None
    try:
        o1, o2 = (float(x) for x in text.split(","))
    except ValueError:
        raise UsageError(f"--steer expects two numbers O1,O2 in [-1, 1], got {text!r}") from None
    if not all(-1.0 <= v <= 1.0 for v in (o1, o2)):
        raise UsageError(f"--steer values must lie in [-1, 1], got {text!r}")
    return (o1, o2)


def _episode_config(args: argparse.Namespace) -> object:
    from neurowalk.arenas import make_arena
    from neurowalk.sim.episode import EpisodeConfig

    variant, params = _variant(args)
    try:
        cfg = EpisodeConfig(arena=args.arena, arena_opts=_arena_opts(args.arena_opt), controller=args.controller,
                            steer=_steer(args.steer), body=args.body, steps=args.steps, seed=args.seed,
                            reflexes=args.reflexes or args.climb, backbone=args.backbone or args.climb,
                            variant=variant, params=params, gait=args.gait)  # fmt: skip
        make_arena(cfg.arena, **cfg.arena_opts)  # validate the arena's options before any work
    except ValueError as e:
        raise UsageError(str(e)) from None
    return cfg


def _run(args: argparse.Namespace) -> int:
    if args.video and args.body != "amosii":
        raise UsageError(f"--video needs --body amosii (the {args.body!r} body has no 3-D state to render)")
    if args.video:
        from neurowalk.render import check_gl, use_headless_gl

        use_headless_gl()
        problem = check_gl()  # before the run, not after it
        if problem:
            raise UsageError(f"--video: {problem}")
    cfg = _episode_config(args)
    from neurowalk.fileio import atomic_write, write_json
    from neurowalk.plotting import plot_run
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
        if cfg.body == "amosii":  # type: ignore[attr-defined]
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
            checkpoint=parts.write_checkpoint if cfg.body == "amosii" else None,
        )  # type: ignore[attr-defined]
    except RunInterruptedError as stop:
        ep, interrupted = stop.episode, True
    done = ep.summary["steps"]  # completed steps
    with _signals_held():  # a signal now would lose the finished run: the save finishes first
        if done:
            parts.join(out / "trajectory.npz", done)
        write_json(out / "summary.json", ep.summary)
        resumable = interrupted and parts.folder.is_dir() and parts.read_checkpoint() is not None
        if not resumable:
            parts.remove()
        if not interrupted:
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
    print(
        f"{cfg.arena}/{cfg.controller}: {s['steps']} steps in {s['wall_time_s']:.1f} s "  # type: ignore[attr-defined]
        f"({s['real_time_factor']:.0f}x real time); moved {s['forward_displacement_m']:+.2f} m, "
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
def _signals_held() -> Iterator[None]:
    """Ignore Ctrl-C and SIGTERM inside the block (the final save of a run), then restore the handlers."""
    import signal

    old = {sig: signal.signal(sig, signal.SIG_IGN) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)


def _view(args: argparse.Namespace) -> int:
    from neurowalk.render import has_display, view

    cfg = _episode_config(args)
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


def _calibrate(args: argparse.Namespace) -> int:
    if args.workers < 1:
        raise UsageError(f"--workers must be >= 1, got {args.workers}")
    from neurowalk.experiments.calibration import calibrate, plot_calibration
    from neurowalk.fileio import atomic_write, write_json

    out_file(args.out)  # before the minute of measuring
    grid = {"grid": (-1.0, -0.3, 0.0, 0.3, 1.0), "held_out": (-0.6, 0.6)} if args.quick else {}
    cal = calibrate(**grid, workers=args.workers)  # type: ignore[arg-type]
    write_json(args.out, cal.to_json())
    fig = plot_calibration(cal)
    png = args.out.with_suffix(".png")
    atomic_write(png, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    v = cal.meta["validation"]
    print(f"calibration: lag {cal.tau_s} s + {cal.delay_steps} steps, start-up {cal.startup_steps} steps; "
          f"held-out error max {v['speed_error_max']:.1%} (speed), {v['yaw_rate_error_max']:.1%} (turning); "
          f"wrote {args.out}, {png}")  # fmt: skip
    return 0


def _bench(args: argparse.Namespace) -> int:
    if args.workers is not None and args.workers < 1:
        raise UsageError(f"--workers must be >= 1, got {args.workers}")
    from neurowalk.bench import run_bench
    from neurowalk.fileio import write_json

    out_folder(args.out)
    r = run_bench(quick=args.quick, workers=args.workers)
    write_json(args.out / "bench.json", r)
    b = r["batch_physics"]["speedup_vs_single_loop"]
    line = (f"physics {r['physics']['control_steps_per_s']:.0f} control steps/s; surrogate "
            f"{r['surrogate']['env_steps_per_s_pool']:.3g} env steps/s ({r['surrogate_vs_physics']['pool']:.0f}x); "
            f"mujoco.batch speed-up {', '.join(f'{k} {v:.2f}x' for k, v in b.items())}")  # fmt: skip
    if "table2_surrogate" in r:
        line += f"; Table 2 (50 environments, surrogate) {r['table2_surrogate']['wall_s']:.1f} s"
    print(f"{line}; wrote {args.out / 'bench.json'}")
    return 0


def _arenas(args: argparse.Namespace) -> int:
    import inspect

    from neurowalk.arenas import ARENAS, arena_options

    for name in sorted(ARENAS):
        doc = (inspect.getdoc(ARENAS[name]) or "").split("\n")[0]
        opts = ", ".join(f"{k}={v}" for k, v in arena_options(name).items()) or "no options"
        print(f"{name:16s} {doc}\n{'':16s} options: {opts}")
    return 0


def _export(args: argparse.Namespace) -> int:
    from neurowalk.arenas import make_arena
    from neurowalk.body.amosii import export_model

    try:
        arena = make_arena(args.arena, **_arena_opts(args.arena_opt))
    except ValueError as e:
        raise UsageError(str(e)) from None
    path = export_model(out_file(args.out), world=arena.to_mjcf())
    print(f"wrote {path}")
    return 0


def _figure(args: argparse.Namespace) -> int:
    from neurowalk.render import has_display, use_headless_gl

    if not has_display():
        use_headless_gl()  # before MuJoCo is imported: figures with rendered snapshots (fig10)
    from neurowalk.experiments import FIGURES

    if args.name == "list":
        print(figure_listing())
        return 0
    if args.name not in FIGURES:
        raise UsageError(f"unknown figure {args.name!r}; available: {', '.join(sorted(FIGURES))}")
    if not 0 <= args.seed < 2**63:
        raise UsageError(f"--seed must be from 0 to 2**63 - 1, got {args.seed}")
    from neurowalk.experiments import output

    exp = FIGURES[args.name]
    out = args.out or Path("out") / (f"{args.name}-climb" if args.climb else args.name)
    t0 = time.perf_counter()
    if args.replot:
        if not (out / f"{args.name}.json").is_file():
            raise UsageError(f"--replot: no {args.name}.json in {str(out)!r}")
        result = output.load(args.name, out)
    else:
        import inspect

        kwargs = {"quick": args.quick, "seed": args.seed}
        if args.seeds is not None:
            if "seeds" not in inspect.signature(exp.run).parameters:
                raise UsageError(f"figure {args.name!r} takes no --seeds")
            if args.seeds < 1:
                raise UsageError(f"--seeds must be >= 1, got {args.seeds}")
            kwargs["seeds"] = args.seeds
        params = inspect.signature(exp.run).parameters
        if args.body is not None:
            from neurowalk.sim.episode import BODIES

            if "body" not in params:
                raise UsageError(f"figure {args.name!r} takes no --body")
            if args.body not in BODIES:
                raise UsageError(f"unknown body {args.body!r}; expected one of {', '.join(BODIES)}")
            kwargs["body"] = args.body
        if args.climb:
            if "climbing" not in params:
                raise UsageError(f"figure {args.name!r} takes no --climb")
            if kwargs.get("body", "amosii") != "amosii":
                raise UsageError(f"--climb needs --body amosii (the {args.body!r} body has no legs)")
            kwargs["climbing"] = True
            if "body" in params:
                kwargs["body"] = "amosii"
        if args.variant is not None or args.params is not None:
            if "variant" not in params:
                raise UsageError(f"figure {args.name!r} takes no --variant/--params")
            kwargs["variant"], overrides = _variant(args)
            if overrides:
                kwargs["params"] = overrides
        if args.gait is not None:
            from neurowalk.neural.cpg import GAITS

            if "gait" not in params:
                raise UsageError(f"figure {args.name!r} takes no --gait (fig3, fig5 and escape-map do)")
            if args.gait not in GAITS:
                raise UsageError(f"unknown gait {args.gait!r}; expected one of {', '.join(GAITS)}")
            kwargs["gait"] = args.gait
        if args.video:
            if "video" not in params:
                raise UsageError(f"figure {args.name!r} takes no --video (fig8 and fig9 do)")
            kwargs["video"] = True
        if args.arena_opt:
            opts = _arena_opts(args.arena_opt)
            if "size" not in params or set(opts) != {"size"}:
                raise UsageError(f"figure {args.name!r} takes no --arena-opt {', '.join(args.arena_opt)} "
                                 "(table2 and fig6 take size=M)")  # fmt: skip
            from neurowalk.arenas import make_arena

            try:
                kwargs["size"] = float(opts["size"])
                make_arena("random", size=kwargs["size"], n_boxes=0)  # the arena's own range check
            except ValueError as e:
                raise UsageError(f"--arena-opt size={opts['size']}: {e}") from None
        if "out" in params:
            kwargs["out"] = out  # the figure keeps a resumable result store there
        out_folder(out)
        from neurowalk.runners.store import StoreError

        try:
            result = exp.run(**kwargs)
        except StoreError as e:
            raise UsageError(str(e)) from None
        except KeyboardInterrupt:
            print(f"neurowalk: {args.name} interrupted; the finished runs are kept in {out}: run the same command "
                  "again to resume (figures without a store there start over)", file=sys.stderr)  # fmt: skip
            return 130
    paths = {} if args.replot else output.save_data(result, out)  # the numbers first: a plot error loses nothing
    paths = {"png": output.save_figure(result, exp.plot(result), out), **paths}
    print(f"{args.name}: wrote {', '.join(str(p) for p in paths.values())} in {time.perf_counter() - t0:.1f} s")
    return 0


_GRID_FLAGS = ("arena", "controller", "body", "seeds", "seed_start", "steps", "arena_opt", "variant", "params", "gait")


def _sweep_specs(args: argparse.Namespace) -> list[dict]:
    """The run specs of `neurowalk sweep`: from --specs, or the grid of the other options."""
    from neurowalk.runners.specs import grid, read_jsonl

    if args.specs is not None:
        given = [f"--{f.replace('_', '-')}" for f in _GRID_FLAGS if getattr(args, f) not in (None, [])]
        if given:
            raise UsageError(f"--specs replaces the grid options; drop {', '.join(given)}")
        try:
            specs = read_jsonl(args.specs)
        except ValueError as e:
            raise UsageError(str(e)) from None
        if not specs:
            raise UsageError(f"no run specs in {str(args.specs)!r}")
        return specs
    seeds, start = args.seeds if args.seeds is not None else 1, args.seed_start or 0
    if seeds < 1:
        raise UsageError(f"--seeds must be >= 1, got {seeds}")
    if start < 0:
        raise UsageError(f"--seed-start must be >= 0, got {start}")
    if start + seeds > 2**63:
        raise UsageError(f"--seed-start {start} + --seeds {seeds}: run seeds must stay below 2**63")
    axes: dict[str, list] = {}
    for flag, default in (("arena", "open"), ("controller", "plastic"), ("body", "amosii")):
        text = default if getattr(args, flag) is None else getattr(args, flag)
        axes[flag] = [v.strip() for v in text.split(",")]
        if not all(axes[flag]):
            raise UsageError(f"--{flag} expects NAME[,NAME...], got {text!r}")
    for key, values in _arena_opts(args.arena_opt).items():
        axes[f"arena_opts.{key}"] = values.split(",")
    base: dict = {} if args.steps is None else {"steps": args.steps}
    variants = [v.strip() for v in args.variant.split(",")] if args.variant is not None else []
    if not all(variants):
        raise UsageError(f"--variant expects NAME[,NAME...], got {args.variant!r}")
    if args.params is not None:  # the file's own base variant unless --variant names others
        file_variant, base["params"] = _variant(argparse.Namespace(variant=None, params=args.params))
        variants = variants or [file_variant]
    if variants:
        axes["variant"] = variants
    if args.gait is not None:
        axes["gait"] = [g.strip() for g in args.gait.split(",")]
        if not all(axes["gait"]):
            raise UsageError(f"--gait expects NAME[,NAME...], got {args.gait!r}")
    axes["seed"] = list(range(start, start + seeds))
    return grid(base, **axes)


def _sweep(args: argparse.Namespace) -> int:
    import importlib.util

    from neurowalk.fileio import write_json
    from neurowalk.runners import ray_backend
    from neurowalk.runners.specs import check_specs
    from neurowalk.runners.store import ResultStore, StoreError
    from neurowalk.runners.sweep import run_sweep

    if args.workers < 1:
        raise UsageError(f"--workers must be >= 1, got {args.workers}")
    if args.retries < 0:
        raise UsageError(f"--retries must be >= 0, got {args.retries}")
    if args.address and args.backend != "ray":
        raise UsageError(f"--address {args.address!r} goes with --backend ray")
    specs = _sweep_specs(args)
    try:
        check_specs(specs)  # every bad name or value exits here, before any work
        if args.backend == "ray":
            ray_backend.import_ray()  # a missing ray is bad input; a broken ray install raises as it is
    except (ValueError, ray_backend.RayMissingError) as e:
        raise UsageError(str(e)) from None
    if args.export == "parquet" and importlib.util.find_spec("pyarrow") is None:
        raise UsageError("--export parquet needs `pip install neurowalk[parquet]`")
    out = out_folder(args.out)
    settings = {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items() if k != "command"}
    info: dict = {"command": "sweep", "settings": settings, "finished": False}
    try:
        store = ResultStore(out / "results.sqlite")
    except StoreError as e:
        raise UsageError(str(e)) from None
    with store:
        write_json(out / "sweep.json", info)
        try:
            report = run_sweep(specs, store, backend=args.backend, workers=args.workers, address=args.address,
                               progress=not args.quiet, retries=args.retries)  # fmt: skip
        except ray_backend.RayStartError as e:
            raise UsageError(str(e)) from None
        written = [out / "results.sqlite", out / "sweep.json"]
        if args.export and not report.interrupted:
            written.append(store.export(out / f"results.{args.export}", args.export))
        failures = [{"key": f.key, "spec": f.spec, "error": f.error} for f in report.failures]
        info.update(finished=not report.interrupted, counts=report.counts(), store=store.counts(), failures=failures)
        write_json(out / "sweep.json", info)
    for f in report.failures[:50]:
        print(f"neurowalk: run failed: {f.line()}", file=sys.stderr)
    if len(report.failures) > 50:
        print(f"neurowalk: ... and {len(report.failures) - 50} more failed runs (all in {out / 'sweep.json'})",
              file=sys.stderr)  # fmt: skip
    r = report
    print(f"sweep: {r.unique} runs: {r.skipped} already done, {r.ok} ok, {r.error} failed, in {r.wall_time_s:.1f} s; "
          f"wrote {', '.join(str(p) for p in written)}")  # fmt: skip
    if r.interrupted:
        print(f"neurowalk: sweep interrupted; the finished runs are in {out / 'results.sqlite'}: run the same command "
              "again to resume", file=sys.stderr)  # fmt: skip
        return 130
    return 1 if r.error else 0


def _optimize_parser(sub: argparse._SubParsersAction) -> None:
    o = sub.add_parser("optimize", help="CMA-ES over the learning parameters on the surrogate: writes DIR/best.json, "
                       "heldout.json, convergence.png (resumable)")  # fmt: skip
    o.add_argument("--out", type=Path, default=Path("out/optimize"), help="output folder (default out/optimize)")
    o.add_argument("--quick", action="store_true", help="small search (6 x 5 candidates, 16 environments, 10000 steps)")
    o.add_argument("--variant", default="original", help="base variant: original (default) | paper")
    o.add_argument("--fields", default=None, metavar="NAME[,NAME...]",
                   help="SensoryParams fields to search (default mu_b,mu_q,gamma_b,gamma_q,k)")  # fmt: skip
    o.add_argument("--param", action="append", default=[], metavar="FIELD=LO:HI",
                   help="bounds of a field (adds it to the search), e.g. mu_b=0.001:0.03; repeatable")  # fmt: skip
    for flag, what in (("population", "candidates per generation (full 8, quick 6)"),
                       ("generations", "generations (full 12, quick 5)"),
                       ("environments", "training environments (full 80, quick 16)"),
                       ("heldout", "held-out environments (full 200, quick 50)"),
                       ("steps", "control steps per environment (full 20000, quick 10000)"),
                       ("deadend-seeds", "seeds per dead-end geometry (full 3, quick 2)")):  # fmt: skip
        o.add_argument(f"--{flag}", type=int, default=None, help=what)
    o.add_argument("--seed", type=int, default=0, help="CMA-ES seed (default 0)")
    o.add_argument("--train-seed", type=int, default=1000, help="table seed of the training environments (1000)")
    o.add_argument("--heldout-seed", type=int, default=0, help="table seed of the held-out environments (0)")
    o.add_argument("--sigma0", type=float, default=0.2, help="initial step size in the normalised space (0.2)")
    o.add_argument("--backend", choices=("local", "ray"), default="local", help="local process pool or Ray")
    o.add_argument("--address", default=None, help="Ray cluster to join (backend ray; default: a local instance)")
    o.add_argument("--workers", type=int, default=2, help="processes, or CPUs of a local Ray instance (default 2)")
    o.add_argument("--quiet", action="store_true", help="no progress bar")


def _optimize(args: argparse.Namespace) -> int:
    from neurowalk.experiments import optimize
    from neurowalk.experiments.optimize_space import parse_bounds
    from neurowalk.runners import ray_backend

    if args.address and args.backend != "ray":
        raise UsageError(f"--address {args.address!r} goes with --backend ray")
    sizes = {k: getattr(args, k) for k in ("population", "generations", "environments", "heldout", "steps",
                                           "deadend_seeds") if getattr(args, k) is not None}  # fmt: skip
    fields = None if args.fields is None else [f.strip() for f in args.fields.split(",")]
    t0 = time.perf_counter()
    try:
        if args.backend == "ray":
            ray_backend.import_ray()
        bounds = dict(parse_bounds(p) for p in args.param)
        optimize.run(out=args.out, quick=args.quick, variant=args.variant, fields=fields, bounds=bounds,
                     sizes=sizes, seed=args.seed, train_seed=args.train_seed, heldout_seed=args.heldout_seed,
                     sigma0=args.sigma0, backend=args.backend, workers=args.workers, address=args.address,
                     progress=not args.quiet, log=lambda line: print(line, flush=True))  # fmt: skip
    except (ValueError, ray_backend.RayMissingError, ray_backend.RayStartError, optimize.CmaMissingError) as e:
        raise UsageError(str(e)) from None
    except KeyboardInterrupt:
        print(f"neurowalk: optimize interrupted; finished runs and generations are in {args.out}: run the same "
              "command again to resume", file=sys.stderr)  # fmt: skip
        return 130
    except RuntimeError as e:
        print(f"neurowalk: optimize: {e}", file=sys.stderr)
        return 1
    print(f"optimize: done in {time.perf_counter() - t0:.1f} s")
    return 0


def parse(argv: list[str]) -> argparse.Namespace:
    """The parsed command line (raises UsageError on a bad one); nothing runs."""
    argv = list(argv)
    # `--steer -1,-1` would read as an option: glue the value on (`--steer=-1,-1`).
    for i, a in enumerate(argv[:-1]):
        if a == "--steer":
            argv[i : i + 2] = [f"--steer={argv[i + 1]}"]
            break
    return _parser().parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``neurowalk`` command; returns the exit status."""
    try:
        args = parse(list(sys.argv[1:] if argv is None else argv))
        commands = {"figure": _figure, "run": _run, "view": _view, "arenas": _arenas, "export-model": _export,
                    "calibrate": _calibrate, "bench": _bench}  # fmt: skip
        commands["sweep"] = _sweep
        commands["optimize"] = _optimize
        return commands[args.command](args)
    except UsageError as e:
        print(f"neurowalk: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
