"""Command line: ``neurowalk figure NAME --out DIR`` and friends. Thin: parses, calls the library.

Bad input exits with status 2 and one line on stderr naming the offending value. The commands live in the modules
of this package by what they run (``figure``, ``run``, ``sweep``, ``optimize``, ``tools``, ``baseline``);
``common`` holds what they share.
"""

from __future__ import annotations

import argparse
import contextlib
import sqlite3
import sys
from collections.abc import Sequence

from neurowalk import __version__
from neurowalk.cli.baseline import add_baseline_parser, cmd_baseline
from neurowalk.cli.common import Parser, UsageError, failed, out_file, out_folder
from neurowalk.cli.figure import add_figure_parser, cmd_figure, figure_listing
from neurowalk.cli.optimize import add_optimize_parser, cmd_optimize
from neurowalk.cli.reproduce import add_reproduce_parser, cmd_reproduce
from neurowalk.cli.run import add_run_parsers, cmd_run
from neurowalk.cli.study import add_study_parser, cmd_study
from neurowalk.cli.sweep import add_sweep_parser, cmd_sweep
from neurowalk.cli.tools import add_tool_parsers, cmd_arenas, cmd_bench, cmd_bodies, cmd_calibrate, cmd_export
from neurowalk.cli.view import add_view_parser, cmd_view
from neurowalk.fileio import write_error
from neurowalk.runners.stopping import stop_on_signals, stop_status

__all__ = ["UsageError", "build_parser", "figure_listing", "main", "out_file", "out_folder", "parse"]

_COMMANDS = {
    "figure": cmd_figure,
    "study": cmd_study,
    "reproduce": cmd_reproduce,
    "run": cmd_run,
    "view": cmd_view,
    "calibrate": cmd_calibrate,
    "bench": cmd_bench,
    "arenas": cmd_arenas,
    "bodies": cmd_bodies,
    "export-model": cmd_export,
    "sweep": cmd_sweep,
    "optimize": cmd_optimize,
    "baseline": cmd_baseline,
}


def build_parser(named: str | None = None) -> argparse.ArgumentParser:
    """The `neurowalk` command's parser: every command and option (nothing runs). ``named``: the figure or the study
    file the command line names, whose settings alone the help of `figure` or `study` shows."""
    p = Parser(prog="neurowalk", description="Adaptive neural control of the hexapod AMOSII (Grinke et al. 2015).")
    p.add_argument("--version", action="version", version=f"neurowalk {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=Parser)
    add_figure_parser(sub, named)
    add_study_parser(sub, named)
    add_reproduce_parser(sub)
    add_run_parsers(sub)
    add_view_parser(sub)
    add_tool_parsers(sub)  # calibrate, bench, arenas, bodies, export-model
    add_sweep_parser(sub)
    add_optimize_parser(sub)
    add_baseline_parser(sub)
    return p


def parse(argv: list[str]) -> argparse.Namespace:
    """The parsed command line (raises UsageError on a bad one); nothing runs."""
    argv = list(argv)
    # `--steer -1,-1` would read as an option: glue the value on (`--steer=-1,-1`).
    for i, a in enumerate(argv[:-1]):
        if a == "--steer":
            argv[i : i + 2] = [f"--steer={argv[i + 1]}"]
            break
    for a in argv:  # argparse reads `--name=--` as an empty list, not as the text "--"
        name, eq, value = a.partition("=")
        if a.startswith("--") and eq and value == "--":
            raise UsageError(f"{name} expects a value, got '--'")
    named = next((a for a in argv[1:] if not a.startswith("-")), None) if argv[:1] in (["figure"], ["study"]) else None
    return build_parser(named).parse_args(argv)


def one_line(text: str) -> str:
    """``text`` with line breaks and other characters a terminal would not print as they are escaped (``\\n``,
    ``\\x1b``, a lone surrogate from bytes that were not UTF-8): the one line of an error, whatever the input."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


MAX_WORKERS = 4096  # processes or Ray CPUs one command asks for


def check_workers(workers: int | None) -> None:
    """UsageError unless ``--workers`` is None (the default) or a count from 1 to :data:`MAX_WORKERS`."""
    if workers is not None and workers < 1:
        raise UsageError(f"--workers must be >= 1, got {workers}")
    if workers is not None and workers > MAX_WORKERS:
        shown = str(workers) if workers < 10**12 else f"a number of {len(str(workers))} digits"
        raise UsageError(f"--workers must be at most {MAX_WORKERS:,}, got {shown}")


def _kept(args: argparse.Namespace | None) -> str:
    """What a command stopped by a write error keeps, in words."""
    out = getattr(args, "out", None)
    if out is None:
        return "nothing half-written is left; fix the cause and run the same command again"
    return f"what was finished is kept in {out}; fix the cause (e.g. free space), then run the same command again"


def _quiet(quiet: bool) -> contextlib.AbstractContextManager[None]:
    """A command's ``--quiet`` silences the compile note too (:func:`neurowalk.progress.quiet_notes`, imported only
    then: it loads tqdm, which a command line that is refused does not need)."""
    if not quiet:
        return contextlib.nullcontext()
    from neurowalk.progress import quiet_notes

    return quiet_notes()


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``neurowalk`` command on ``argv`` (default ``sys.argv[1:]``); returns the exit status.

    The first SIGINT or SIGTERM while it runs stops it with one line and exit status 130 (SIGINT) or 143 (SIGTERM).
    The command itself goes through :mod:`neurowalk.__main__`, which answers them from its first moment.
    """
    with stop_on_signals():
        return _main(argv)


def _main(argv: Sequence[str] | None) -> int:
    args = None
    try:
        args = parse(list(sys.argv[1:] if argv is None else argv))
        check_workers(getattr(args, "workers", None))  # every command's --workers, in one place
        with _quiet(getattr(args, "quiet", False)):
            return _COMMANDS[args.command](args)
    except UsageError as e:
        print(f"neurowalk: error: {one_line(str(e))}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C or SIGTERM where a command has no words of its own (e.g. while it starts)
        print("neurowalk: interrupted", file=sys.stderr)
        return stop_status()  # 130, or 143 for SIGTERM
    except BrokenPipeError:  # the reader went away (e.g. `neurowalk figure list | head`): not an error
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no second error when Python flushes
        return 0
    except OSError as e:  # a write that failed part-way (disk full, quota, a folder removed or made read-only)
        return failed(f"neurowalk: {write_error(e)}; {_kept(args)}")
    except sqlite3.OperationalError as e:  # the result store could not be written (e.g. "database or disk is full")
        return failed(f"neurowalk: the result store could not be written ({e}); {_kept(args)}")
