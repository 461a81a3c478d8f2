"""The `figure` command: reproduce a paper figure (or redraw it from its saved numbers), and the list of figures."""

from __future__ import annotations

import argparse
from pathlib import Path

from neurowalk.cli.common import UsageError, stop_line, usage_errors
from neurowalk.cli.settings import add_settings_args, figure_settings
from neurowalk.runners.stopping import deferred


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


def cmd_figure(args: argparse.Namespace) -> int:
    """`neurowalk figure NAME`: run the figure (or --replot it), write DIR/NAME.png and its numbers.

    The flags are parsed once into Settings here; :func:`~neurowalk.experiments.command.run_command` does the rest.
    The first SIGINT or SIGTERM stops it (exit 130, or 143 for SIGTERM) with one line saying what its result stores
    hold: a figure of many runs keeps each finished one there, and the same command again goes on from them.
    """
    try:
        with deferred():  # every figure's modules (numba's, MuJoCo's) load whole: a signal now stops it right after
            from neurowalk.experiments import FIGURES
            from neurowalk.experiments.command import CommandError, run_command
    except KeyboardInterrupt:
        return stop_line(f"neurowalk: figure {args.name} interrupted before it began; nothing was run")
    if args.name == "list":
        print(figure_listing(times=True))
        return 0
    if args.name not in FIGURES:
        raise UsageError(f"unknown figure {args.name!r}; available: {', '.join(sorted(FIGURES))}")
    study = FIGURES[args.name]
    settings = figure_settings(args, study)
    with usage_errors(CommandError):
        return run_command(study, settings, f"figure {args.name}", replot=args.replot)
