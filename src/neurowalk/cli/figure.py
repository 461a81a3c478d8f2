"""The `figure` command: reproduce a paper figure (or redraw it from its saved numbers), and the list of figures."""

from __future__ import annotations

import argparse
import functools
import sys
import time
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from neurowalk.cli.common import (
    UsageError,
    check_engine,
    control_hz_arg,
    engine_args,
    out_folder,
    parse_arena_opts,
    parse_variant,
    variant_args,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from neurowalk.experiments import Result

# The figure flags that only some figures take: flag -> (the parameter of the figure's run() that takes it, which
# figures do, for the message).
_TAKES = {
    "--seeds": ("seeds", ""),
    "--body": ("body", ""),
    "--climb": ("climbing", ""),
    "--variant/--params": ("variant", ""),
    "--gait": ("gait", " (fig3, fig5 and escape-map do)"),
    "--video": ("video", " (fig8 and fig9 do)"),
    "--arena-opt": ("size", " (table2 and fig6 take size=M)"),
    "--engine": ("engine", " (fig3, fig5 and table2 do)"),
    "--control-hz": ("control_hz", " (the physics figures do)"),
    "--workers": ("workers", " (figures of many runs do)"),
}


MAX_SEEDS = 100_000  # the most environments or seeds a figure takes (--seeds)


def figure_listing(times: bool = False) -> str:
    """The figures, one per line: name and one-line description, aligned; ``times``: then the committed run's
    times of ``--quick`` and full, and the machine they were measured on."""
    from neurowalk.experiments import FIGURES

    width = max(len(n) for n in FIGURES) + 2
    if not times:
        return "\n".join(f"{name:<{width}}{exp.title}" for name, exp in sorted(FIGURES.items()))
    from neurowalk.experiments.reproduce.timing import describe, figure_times

    lines = []
    for name, exp in sorted(FIGURES.items()):
        took = describe(name)
        lines.append(f"{name:<{width}}{exp.title}" + (f" [{took}]" if took else ""))
    machine = figure_times().get("machine")
    lines.append(f"[times: the committed `neurowalk reproduce` run, docs/results/, on {machine or 'no machine yet'}]")
    return "\n".join(lines)


def add_figure_parser(sub: argparse._SubParsersAction) -> None:
    """The `figure` subcommand; its help ends with the list of figures."""
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
    f.add_argument(
        "--body", default=None, help="{bodies} (figures that take a body; default per figure; see `neurowalk bodies`)"
    )
    climb = "leg reflexes and backbone control on (fig3 fig5 escape-map table2; default out: out/NAME-climb)"
    f.add_argument("--climb", action="store_true", help=climb)
    variant_args(f)
    f.add_argument(
        "--gait", default=None, help="gait of the physics figures that take one (fig3 fig5 escape-map): {gaits}"
    )
    f.add_argument("--video", action="store_true", help="also write the example runs' videos (fig8, fig9)")
    f.add_argument(
        "--arena-opt",
        action="append",
        default=[],
        metavar="size=M",
        help="box side of the random environments (table2, fig6; default 1 m, the authors')",
    )
    control_hz_arg(f, default=None)
    f.add_argument("--workers", type=int, default=None, help="processes of figures of many runs (default 2)")
    engine_args(f)


def _rate_suffix(control_hz: float | None) -> str:
    """The default output folder's suffix for a control rate: "" at the default 10 Hz, else "-27hz"."""
    if control_hz is None or control_hz == 10.0:
        return ""
    return f"-{control_hz:g}hz"


def _check_takes(name: str, params: Mapping[str, object], flag: str, given: str = "", ok: bool = True) -> None:
    """UsageError unless figure ``name``, whose run() has the parameters ``params``, takes ``flag``.

    ``given``: the flag's values, named in the message; ``ok``: false where the figure takes the flag but not those.
    """
    param, which = _TAKES[flag]
    if param not in params or not ok:
        raise UsageError(f"figure {name!r} takes no {flag}{given}{which}")


def cmd_figure(args: argparse.Namespace) -> int:
    """`neurowalk figure NAME`: run the figure (or --replot it), write DIR/NAME.png and its numbers.

    The first SIGINT or SIGTERM stops it (exit 130, or 143 for SIGTERM) with one line saying what its result stores
    hold: a figure of many runs keeps each finished one there, and the same command again goes on from them.
    """
    from neurowalk.runners.stopping import interrupted, stop_on_signals, stop_status

    with stop_on_signals():
        try:
            return _figure(args)
        except (KeyboardInterrupt, Exception) as e:  # while it started (a run's own stop is answered inside)
            if not interrupted(e):
                raise
            print(f"neurowalk: figure {args.name} interrupted before it began; nothing was run", file=sys.stderr)
            return stop_status()


def _figure(args: argparse.Namespace) -> int:
    from neurowalk.render import has_display, use_headless_gl
    from neurowalk.runners.stopping import deferred, interrupted, stop_status

    if not has_display():
        use_headless_gl()  # before MuJoCo is imported: figures with rendered snapshots (fig10)
    with deferred():  # every figure's modules (numba's, MuJoCo's) load whole: a signal now stops it right after
        from neurowalk.body.registry import bodies_where
        from neurowalk.experiments import FIGURES
        from neurowalk.sim.config import DEFAULT_ENGINE

    if args.name == "list":
        print(figure_listing(times=True))
        return 0
    if args.name not in FIGURES:
        raise UsageError(f"unknown figure {args.name!r}; available: {', '.join(sorted(FIGURES))}")
    if not 0 <= args.seed < 2**63:
        raise UsageError(f"--seed must be from 0 to 2**63 - 1, got {args.seed}")
    from neurowalk.experiments import output

    exp = FIGURES[args.name]
    out = args.out or Path("out") / (args.name + ("-climb" if args.climb else "") + _rate_suffix(args.control_hz))
    t0 = time.perf_counter()
    if args.replot:
        if not (out / f"{args.name}.json").is_file():
            raise UsageError(f"--replot: no {args.name}.json in {str(out)!r}; run the figure without --replot first")
        result, picture = _replot(args.name, out)
    else:
        import inspect

        params = inspect.signature(exp.run).parameters
        takes = functools.partial(_check_takes, args.name, params)
        kwargs = {"quick": args.quick, "seed": args.seed}
        if args.seeds is not None:
            takes("--seeds")
            if not 1 <= args.seeds <= MAX_SEEDS:
                raise UsageError(
                    f"--seeds must be in [1, {MAX_SEEDS:,}] (each seed is a run of every row, held in "
                    f"memory until the figure is drawn), got {args.seeds:,}"
                )
            kwargs["seeds"] = args.seeds
        if args.body is not None:
            from neurowalk.sim.episode import BODIES

            takes("--body")
            kwargs["body"] = known("body", args.body, BODIES)
        if args.climb:
            takes("--climb")
            climbers = bodies_where(lambda b: b.climbs)
            if kwargs.get("body", climbers[0]) not in climbers:
                raise UsageError(f"--climb needs --body {climbers[0]} (the {args.body!r} body has no legs)")
            kwargs["climbing"] = True
            if "body" in params:
                kwargs["body"] = kwargs.get("body", climbers[0])
        if args.variant is not None or args.params is not None:
            takes("--variant/--params")
            kwargs["variant"], overrides = parse_variant(args)
            if overrides:
                kwargs["params"] = overrides
        if args.gait is not None:
            from neurowalk.neural.cpg import GAITS

            takes("--gait")
            kwargs["gait"] = known("gait", args.gait, tuple(GAITS))
        if args.engine != DEFAULT_ENGINE or args.device is not None:
            takes("--engine")
            runs = bodies_where(lambda b: args.engine in b.engines)
            if not runs:  # no body runs on it: not an engine's name
                check_engine(args)
            if "body" in params:  # e.g. Warp runs the physics AMOSII only
                if kwargs.get("body", runs[0]) not in runs:
                    raise UsageError(f"--engine {args.engine} runs --body {runs[0]}, got --body {kwargs['body']!r}")
                kwargs["body"] = kwargs.get("body", runs[0])
            kwargs["engine"] = args.engine
            device = check_engine(args).device
            if "device" in params:
                kwargs["device"] = device
        if args.workers is not None:
            takes("--workers")
            kwargs["workers"] = args.workers
        if args.control_hz is not None:
            takes("--control-hz")
            if not 0 < args.control_hz <= 1000:  # also NaN
                raise UsageError(f"--control-hz must be a number in (0, 1000] Hz, got {args.control_hz}")
            kwargs["control_hz"] = args.control_hz
            if "body" in params:  # a planar surrogate runs at its calibration's rate only: refused before any work
                from neurowalk.sim.config import EpisodeConfig

                body = kwargs.get("body", params["body"].default)
                try:
                    EpisodeConfig(body=body, control_hz=args.control_hz)
                except ValueError as e:
                    raise UsageError(f"--control-hz {args.control_hz:g}: {e} (add --body amosii)") from None
        if args.video:
            takes("--video")
            kwargs["video"] = True
        if args.arena_opt:
            opts = parse_arena_opts(args.arena_opt)
            takes("--arena-opt", given=f" {', '.join(args.arena_opt)}", ok=set(opts) == {"size"})
            from neurowalk.arenas import make_arena

            try:
                kwargs["size"] = float(opts["size"])
                make_arena("random", size=kwargs["size"], n_boxes=0)  # the arena's own range check
            except ValueError as e:
                raise UsageError(f"--arena-opt size={opts['size']}: {e}") from None
        if "out" in params:
            kwargs["out"] = out  # the figure keeps a resumable result store there
        existed = out.exists()
        out_folder(out)
        from neurowalk.runners.store import StoreError
        from neurowalk.sim.episode import RunInterruptedError

        try:
            result = exp.run(**kwargs)
        except StoreError as e:
            raise UsageError(str(e)) from None
        except ValueError as e:  # a figure checks its settings before it runs (e.g. a surrogate at 27 Hz)
            if not existed and not any(out.iterdir()):
                out.rmdir()  # made for this command, still empty: leave nothing behind
            raise UsageError(f"figure {args.name}: {e}") from None
        except (KeyboardInterrupt, Exception) as e:  # RunInterruptedError: a run in this process, stopped part-way
            if not (interrupted(e) or isinstance(e, RunInterruptedError)):
                raise
            print(interrupted_line(args.name, out, "out" in params), file=sys.stderr)
            return stop_status()

    paths: dict[str, Path] = {}
    try:
        if not args.replot:
            with deferred():  # the numbers first, whole: a plot error (or a Ctrl-C while drawing) loses nothing
                paths = output.save_data(result, out)
            picture = exp.plot(result)
        with deferred():
            paths = {"png": output.save_figure(result, picture, out), **paths}
    except KeyboardInterrupt:
        files = ", ".join(str(p) for p in paths.values())
        if "png" in paths:
            line = f"neurowalk: {args.name} interrupted as it ended; it wrote {files}"
        elif paths:
            line = f"neurowalk: {args.name} interrupted while drawing: its numbers are in {files}; `--replot` draws it"
        elif args.replot:
            line = f"neurowalk: {args.name} interrupted while drawing; nothing written"
        else:
            line = interrupted_line(args.name, out, "out" in params)
        print(line, file=sys.stderr)
        return stop_status()
    print(f"{args.name}: wrote {', '.join(str(p) for p in paths.values())} in {time.perf_counter() - t0:.1f} s")
    return 0


def _replot(name: str, out: Path) -> tuple[Result, Figure]:
    """Figure ``name``'s numbers saved in ``out``, and their picture; UsageError naming the file where they cannot be
    read or are not this figure's (damaged, truncated, foreign), which is left as it is."""
    import warnings

    from neurowalk.experiments import FIGURES, output

    again = f"rerun `neurowalk figure {name}` without --replot to make them again"
    try:
        result = output.load(name, out)
    except output.DataError as e:
        raise UsageError(f"{e}; {again}") from None
    with warnings.catch_warnings(record=True) as caught:  # shown only where the picture is drawn
        try:
            picture = FIGURES[name].plot(result)
        except Exception as e:  # JSON of another shape: a key, a type or an array missing or odd
            if "matplotlib.pyplot" in sys.modules:
                sys.modules["matplotlib.pyplot"].close("all")
            npz = out / f"{name}.npz"
            files = f"{out / name}.json" + (f", {npz}" if npz.exists() else f" (no {npz.name} beside it)")
            why = " ".join(f"{type(e).__name__}: {e}".split())[:160]
            raise UsageError(f"{files}: not the numbers of figure {name} ({why}); {again}") from None
    for w in caught:
        warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    return result, picture


def interrupted_line(name: str, out: Path, stores: bool) -> str:
    """The line of a figure interrupted while it ran: how many finished runs its result stores in ``out`` hold
    (read from the files), or that it keeps none (``stores``: whether the figure keeps its runs in ``out``)."""
    if not stores:
        return f"neurowalk: {name} interrupted; this figure keeps no runs (a few short ones): run it again"
    from neurowalk.runners.store import count_finished

    kept = {p.name: n for p in sorted(out.glob("*.sqlite")) if (n := count_finished(p))}
    if not kept:
        return f"neurowalk: {name} interrupted before any of its runs finished; nothing is kept"
    where = ", ".join(f"{n} in {file}" for file, n in kept.items())
    return (
        f"neurowalk: {name} interrupted: {sum(kept.values())} finished runs are kept in {out} ({where}); run "
        "the same command again to go on from them"
    )


def known(what: str, name: str, names: tuple[str, ...]) -> str:
    """``name`` if it is one of ``names``, else UsageError: "unknown WHAT 'NAME'; expected one of ..."."""
    if name not in names:
        raise UsageError(f"unknown {what} {name!r}; expected one of {', '.join(names)}")
    return name
