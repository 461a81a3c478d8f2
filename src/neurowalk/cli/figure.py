"""The `figure` command: reproduce a paper figure (or redraw it from its saved numbers), and the list of figures."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from neurowalk.cli.common import UsageError, failure_words, stop_line, stopped
from neurowalk.cli.settings import add_settings_args, run_and_write, settings_of

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from neurowalk.experiments import Result


def figure_listing(times: bool = False) -> str:
    """The figures in the paper's order (the table's), one per line: name and one-line description, aligned;
    ``times``: then the committed run's times of ``--quick`` and full, and the machine they were measured on."""
    from neurowalk.experiments import FIGURES

    width = max(len(n) for n in FIGURES) + 2
    if not times:
        return "\n".join(f"{name:<{width}}{exp.title}" for name, exp in FIGURES.items())
    from neurowalk.experiments.reproduce.timing import describe, figure_times

    lines = []
    for name, exp in FIGURES.items():
        took = describe(name)
        lines.append(f"{name:<{width}}{exp.title}" + (f" [{took}]" if took else ""))
    machine = figure_times().get("machine")
    lines.append(
        f"[times: the committed `neurowalk reproduce` runs, docs/results/, on {machine or 'no machine yet'}; "
        "figures there share their runs, so fig5, bodies and surrogate alone take longer]"
    )
    return "\n".join(lines)


def add_figure_parser(sub: argparse._SubParsersAction, name: str | None = None) -> None:
    """The `figure` subcommand; its help ends with the list of figures. ``name``: the figure the command line
    names, whose settings alone the help shows (None: every setting)."""
    from neurowalk.experiments import FIGURES

    f = sub.add_parser("figure", help="reproduce a paper figure: writes DIR/NAME.png and DIR/NAME.json")
    f.help_tail = lambda: "\nfigures:\n" + "".join(f"  {line}\n" for line in figure_listing().splitlines())
    f.page_tail = "figures: `neurowalk figure list` lists them (and `neurowalk figure --help`)"  # the site's page
    f.add_argument("name", help="figure name (see `neurowalk figure list`)")
    f.add_argument("--replot", action="store_true", help="redraw from DIR/NAME.json and .npz without rerunning")
    f.add_argument(
        "--shared-runs",
        type=Path,
        default=None,
        metavar="RUNS",
        help="keep the runs in the result store of folder RUNS, which figures share (a run another figure made with "
        "the same config is taken, not run again); default: the figure's own store in DIR; `neurowalk reproduce` "
        "shares one",
    )
    f.add_argument(
        "--settings",
        type=Path,
        default=None,
        metavar="FILE",
        dest="settings_file",
        help='take every setting from FILE, a JSON file {"figure": NAME, "settings": {...}} of the settings\' '
        "fields (`neurowalk reproduce` writes one per figure, DIR/RUN/settings.json: a figure of a reproduction "
        "runs again by hand so); no other setting with it",
    )
    add_settings_args(f, FIGURES[name].takes if name in FIGURES else None)


def _rate_suffix(control_hz: float | None) -> str:
    """The default output folder's suffix for a control rate: "" at the default 10 Hz, else "-27hz"."""
    if control_hz is None or control_hz == 10.0:
        return ""
    return f"-{control_hz:g}hz"


def cmd_figure(args: argparse.Namespace) -> int:
    """`neurowalk figure NAME`: run the figure (or --replot it), write DIR/NAME.png and its numbers.

    The first SIGINT or SIGTERM stops it (exit 130, or 143 for SIGTERM) with one line saying what its result stores
    hold: a figure of many runs keeps each finished one there, and the same command again goes on from them.
    """
    return stopped(  # a stop while it starts (a run's own stop is answered inside)
        lambda: _figure(args), lambda: f"neurowalk: figure {args.name} interrupted before it began; nothing was run"
    )


def _figure(args: argparse.Namespace) -> int:
    from neurowalk.render import has_display, use_headless_gl
    from neurowalk.runners.stopping import deferred

    if not has_display():
        use_headless_gl()  # before MuJoCo is imported: figures with rendered snapshots (fig10)
    with deferred():  # every figure's modules (numba's, MuJoCo's) load whole: a signal now stops it right after
        from neurowalk.experiments import FIGURES

    if args.name == "list":
        print(figure_listing(times=True))
        return 0
    if args.name not in FIGURES:
        raise UsageError(f"unknown figure {args.name!r}; available: {', '.join(sorted(FIGURES))}")
    study = FIGURES[args.name]
    if args.settings_file is not None:
        settings = settings_from_file(args, study)
        return run_and_write(study, settings, f"figure {args.name}")
    settings = settings_of(args, study, f"figure {args.name!r}")
    out = args.out or Path("out") / (args.name + ("-climb" if args.climbing else "") + _rate_suffix(args.control_hz))
    if args.replot:
        return _replot(args.name, out)
    return run_and_write(study, settings.replace(out=out, shared_runs=args.shared_runs), f"figure {args.name}")


def settings_from_file(args: argparse.Namespace, study: Any) -> Any:
    """The settings of ``--settings FILE`` for figure ``args.name`` (out: the file's, else ``out/NAME``), checked as
    the flags' are; UsageError in one line naming the file where it cannot be read, names another figure, is given
    with other settings, or holds a setting the figure does not take or a bad value."""
    import dataclasses
    import json

    from neurowalk.experiments.study import Settings, resolve

    path = args.settings_file
    others = settings_of(args, study, f"figure {args.name!r}")  # the flags alongside: none but their defaults
    if others != Settings(out=args.out) or args.shared_runs is not None or args.replot:
        raise UsageError(f"--settings {path}: give no other setting with it (they are all in the file)")
    try:
        text = json.loads(Path(path).read_text(encoding="utf-8"))
        figure, fields = text["figure"], dict(text["settings"])
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise UsageError(f"--settings {path}: not a settings file ({failure_words(e)})") from None
    if figure != args.name:
        raise UsageError(f"--settings {path} holds the settings of figure {figure!r}, not {args.name!r}")
    known = {f.name for f in dataclasses.fields(Settings)}
    if set(fields) - known:
        raise UsageError(f"--settings {path}: unknown settings {sorted(set(fields) - known)}")
    try:
        settings = Settings(**fields)
        study.check(settings)
        settings = resolve(study, settings)
    except (ValueError, TypeError) as e:
        raise UsageError(f"--settings {path}: {e}") from None
    return settings if settings.out is not None else settings.replace(out=Path("out") / args.name)


def _replot(name: str, out: Path) -> int:
    """Redraw figure ``name`` from its numbers in ``out``; UsageError naming the file where they cannot be read or
    are not this figure's (damaged, truncated, foreign), which is left as it is."""
    from neurowalk.experiments import output
    from neurowalk.runners.stopping import deferred

    t0 = time.perf_counter()
    if not (out / f"{name}.json").is_file():
        raise UsageError(f"--replot: no {name}.json in {str(out)!r}; run the figure without --replot first")
    try:
        result, picture = _redraw(name, out)
        with deferred():
            path = output.save_figure(result, picture, out)
    except KeyboardInterrupt:
        return stop_line(f"neurowalk: {name} interrupted while drawing; nothing written")
    print(f"{name}: wrote {path} in {time.perf_counter() - t0:.1f} s")
    return 0


def _redraw(name: str, out: Path) -> tuple[Result, Figure]:
    """Figure ``name``'s numbers saved in ``out``, and their picture."""
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
            why = failure_words(e)  # where the drawing failed too: a bug shows its line
            raise UsageError(f"{files}: not the numbers of figure {name} ({why}); {again}") from None
    for w in caught:
        warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    return result, picture
