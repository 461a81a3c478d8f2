"""The tool commands: `calibrate` (the surrogate's calibration), `bench`, `arenas` and `bodies` (the lists) and
`export-model`."""

from __future__ import annotations

import argparse
from pathlib import Path

from neurowalk.cli.common import (
    UsageError,
    check_engine,
    engine_args,
    option_args,
    out_file,
    out_folder,
    parse_arena_opts,
    stop_line,
    stopped,
    usage_errors,
)
from neurowalk.fileio import atomic_write, write_json
from neurowalk.runners.stopping import deferred


def add_tool_parsers(sub: argparse._SubParsersAction) -> None:
    """The `calibrate`, `bench`, `arenas` and `export-model` subcommands."""
    c = sub.add_parser("calibrate", help="measure a physics body for its planar surrogate (writes a JSON file)")
    c.add_argument(
        "--body",
        default="amosii",
        help="physics body: {calibrated_bodies} (default amosii, for the body "
        "surrogate; wheeled: for surrogate-wheeled)",
    )
    c.add_argument(
        "--out",
        type=Path,
        default=None,
        help="file to write (default out/calibration/ and the name of "
        "the shipped file: calibration.json, calibration-wheeled.json)",
    )
    c.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    c.add_argument("--quick", action="store_true", help="coarse grid (for a smoke test; not for shipping)")

    b = sub.add_parser("bench", help="measure the performance figures side by side: writes DIR/bench.json")
    b.add_argument("--out", type=Path, default=Path("out/bench"), help="output folder (default out/bench)")
    b.add_argument("--quick", action="store_true", help="short measurements (a smoke test)")
    b.add_argument("--workers", type=int, default=None, help="processes / threads (default: the cores, up to 8)")
    engine_args(b)
    b.add_argument(
        "--worlds",
        default="1,64,1024,4096",
        help="engine warp: numbers of worlds to measure (comma list; default 1,64,1024,4096)",
    )

    sub.add_parser("arenas", help="list the arenas and their options")
    sub.add_parser("bodies", help="list the bodies: sensors, actuators, what they take, options")
    e = sub.add_parser("export-model", help="write the robot (and an arena) as a self-contained MJCF file")
    e.add_argument("--out", type=Path, required=True, help="MJCF file to write")
    e.add_argument("--arena", default="open", help="arena to include (default open)")
    option_args(e, "--arena-opt", "KEY=VALUE", "arena option")
    e.add_argument("--body", default="amosii", help="physics body: {physics_bodies} (default amosii)")
    option_args(e, "--body-opt", "KEY=VALUE", "body option, e.g. scale=0.5")


def cmd_calibrate(args: argparse.Namespace) -> int:
    """`neurowalk calibrate`: measure a physics body, write its surrogate's calibration and its plot.

    Its drives are kept in the result store beside the file (``DIR/results.sqlite``) as they finish. The first SIGINT
    or SIGTERM stops it (exit 130, or 143 for SIGTERM) with one line saying what it kept or wrote; the same command
    again goes on from the drives it finished.
    """
    return stopped(lambda: _calibrate(args), lambda: _calibrate_stopped(args))  # a stop while it measured


def _calibrate_stopped(args: argparse.Namespace) -> str:
    """The line of a calibration stopped while it measured: whether drives are kept in its store to go on from."""
    from neurowalk.fingerprint import code
    from neurowalk.runners.store import count_finished

    if args.out is None:
        return "neurowalk: calibrate interrupted before it began; nothing was run"
    store = args.out.parent / "results.sqlite"
    if not store.is_file() or not count_finished(store, code=code()):
        return "neurowalk: calibrate interrupted before any of its drives finished; nothing is kept"
    return (
        f"neurowalk: calibrate interrupted before its measurement ended; the drives it finished are kept in {store}: "
        "run the same command again to go on from them"
    )


def _calibrate(args: argparse.Namespace) -> int:
    with deferred():  # the simulation's modules (numba's, MuJoCo's) load whole: a signal waits for their end
        from neurowalk.body.surrogate import CALIBRATION_FILES
        from neurowalk.experiments.calibration.calibrate import calibrate, plot_calibration
        from neurowalk.experiments.calibration.subjects import subject
        from neurowalk.plotting import look

    with usage_errors():
        sub = subject(args.body)
    if args.out is None:
        args.out = Path("out/calibration") / CALIBRATION_FILES[sub.surrogate].name
    out_file(args.out)  # before the minute of measuring
    grid = {"grid": (-1.0, -0.3, 0.0, 0.3, 1.0), "held_out": (-0.6, 0.6)} if args.quick else {}
    cal = calibrate(**grid, workers=args.workers, body=args.body, folder=args.out.parent)  # type: ignore[arg-type]
    png = args.out.with_suffix(".png")
    written: list[Path] = []
    try:
        with deferred():
            write_json(args.out, cal.to_json())
            written.append(args.out)
        fig = plot_calibration(cal)
        with deferred(), look():
            atomic_write(png, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
            written.append(png)
    except KeyboardInterrupt:
        missing = "" if png in written else ", without its plot"
        return stop_line(f"neurowalk: calibrate interrupted as it ended: wrote {', '.join(map(str, written))}{missing}")
    v = cal.meta["validation"]
    print(
        f"calibration of {sub.surrogate} on {args.body}: lag {cal.tau_s} s + {cal.delay_steps} steps, "
        f"start-up {cal.startup_steps} steps; "
        f"held-out error max {v['speed_error_max']:.2%} (speed), {v['yaw_rate_error_max']:.2%} (turning); "
        f"wrote {args.out}, {png}"
    )
    return 0


def cmd_bench(args: argparse.Namespace) -> int:
    """`neurowalk bench`: the performance figures into DIR/bench.json."""
    try:
        worlds = tuple(int(w) for w in args.worlds.split(","))
    except ValueError:
        raise UsageError(f"--worlds expects whole numbers separated by commas, got {args.worlds!r}") from None
    if not worlds or min(worlds) < 1:
        raise UsageError(f"--worlds expects numbers >= 1, got {args.worlds!r}")
    device = check_engine(args).device
    from neurowalk.experiments.bench import run_bench

    out_folder(args.out)
    r = run_bench(quick=args.quick, workers=args.workers, engine=args.engine, device=device, worlds=worlds)
    write_json(args.out / "bench.json", r)
    b = r["batch_physics"]["speedup_vs_single_loop"]
    ps = r["physics_settings"]
    line = (
        f"physics {r['physics']['control_steps_per_s']:.0f} control steps/s, closed loop / bare mj_step "
        f"{r['closed_loop_vs_bare']['ratio_closed_loop_over_bare']:.2f}; closed loop at the adopted physics "
        f"{ps['control_steps_per_s_adopted']:.0f} control steps/s, at the former "
        f"{ps['control_steps_per_s_former']:.0f} ({ps['adopted_over_former']:.2f}x); "
        f"mujoco.batch speed-up {', '.join(f'{k} {v:.2f}x' for k, v in b.items())}"
    )
    if "surrogate" in r:
        line += (
            f"; surrogate {r['surrogate']['env_steps_per_s_pool']:.3g} env steps/s "
            f"({r['surrogate_vs_physics']['pool']:.0f}x)"
        )
    if "warp" in r:
        w = r["warp"]
        line += (
            f"; warp on {w['device_name']}: best {w['vs_cpu_loop']['best_control_steps_per_s']:.0f} control "
            f"steps/s ({w['vs_cpu_loop']['ratio']:.2f}x the CPU loop)"
        )
    if "table2_surrogate" in r:
        line += f"; Table 2 (50 environments, surrogate) {r['table2_surrogate']['wall_s']:.1f} s"
    print(f"{line}; wrote {args.out / 'bench.json'}")
    return 0


def cmd_arenas(args: argparse.Namespace) -> int:
    """`neurowalk arenas`: each arena, its one-line description and its options."""
    import inspect

    from neurowalk.arenas import ARENAS, arena_options

    for name in sorted(ARENAS):
        doc = (inspect.getdoc(ARENAS[name]) or "").split("\n")[0].replace("``", "")  # plain text, not reST
        opts = ", ".join(f"{k}={v}" for k, v in arena_options(name).items()) or "no options"
        print(f"{name:16s} {doc}\n{'':16s} options: {opts}")
    return 0


def cmd_bodies(args: argparse.Namespace) -> int:
    """`neurowalk bodies`: each body of the registry, what it needs and offers."""
    from neurowalk.body.registry import body_listing

    print(body_listing())
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    """`neurowalk export-model`: the robot (and an arena) as one MJCF file."""
    import mujoco

    from neurowalk.arenas import make_arena
    from neurowalk.body import registry

    with usage_errors():
        arena = make_arena(args.arena, **parse_arena_opts(args.arena_opt))
        opts = registry.check_body_opts(args.body, parse_arena_opts(args.body_opt, "--body-opt"))
        if not registry.body_info(args.body).physics:
            raise ValueError(f"body {args.body!r} is planar: it has no MuJoCo model to export")
    path = out_file(args.out)
    xml = registry.body_xml(args.body, opts, world=arena.to_mjcf())
    mujoco.MjModel.from_xml_string(xml)  # compiles, before anything is written
    atomic_write(path, lambda tmp: Path(tmp).write_text(xml, encoding="utf-8"))
    print(f"wrote {path}")
    return 0
