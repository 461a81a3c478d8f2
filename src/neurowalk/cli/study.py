"""The `study` command: run a study written in a user's Python file, with the settings it takes."""

from __future__ import annotations

import argparse
import sys
import traceback
from pathlib import Path
from typing import Any

from neurowalk.cli.common import UsageError, failed, stop_line, usage_errors
from neurowalk.cli.settings import add_settings_args, settings_of
from neurowalk.runners.stopping import interrupted


def study_of(path: Path) -> object:
    """The study of file ``path``, checked (:func:`~neurowalk.experiments.study_check.check_study`'s structure
    checks; UsageError in one line naming the file, and its line, where it has none or cannot run)."""
    from neurowalk.experiments.study_check import load_study

    with usage_errors():
        return load_study(path)


def add_study_parser(sub: argparse._SubParsersAction, path: str | None = None) -> None:
    """The `study` subcommand. ``path``: the study file the command line names, whose settings alone the help
    shows (None: every setting)."""
    s = sub.add_parser(
        "study",
        help="run your own study (a Python file defining `study = Study(...)`): writes DIR/NAME.png, .json",
        description="Run the study a Python file defines (see the tutorial 'Your own experiment'). Its runs are kept "
        "in DIR/results.sqlite as they finish: stopped, the same command goes on from them. The settings below "
        "are those the study takes (`neurowalk study FILE.py --help` shows the file's own).",
    )
    s.add_argument("file", type=Path, help="the study's Python file")
    takes = None
    if path is not None and Path(path).suffix == ".py" and Path(path).is_file():
        study = study_of(Path(path))  # the file runs once per command: the help and the run share it
        s.set_defaults(study=study, study_file=Path(path))
        takes = study.takes  # type: ignore[attr-defined]
    add_settings_args(s, takes)


def cmd_study(args: argparse.Namespace) -> int:
    """`neurowalk study FILE.py`: run the file's study, write DIR/NAME.png and its numbers (exit 130/143 when
    stopped, keeping the finished runs)."""
    from neurowalk.experiments.command import CommandError, run_command
    from neurowalk.experiments.study_check import check_study

    try:
        loaded = getattr(args, "study", None)
        same = loaded is not None and Path(args.study_file).resolve() == Path(args.file).resolve()
        study = loaded if same else study_of(args.file)
        settings = settings_of(args, study, f"study {study.name!r}")  # type: ignore[attr-defined]
    except (KeyboardInterrupt, Exception) as e:
        if not interrupted(e):
            raise
        return stop_line(f"neurowalk: study {args.file} interrupted before it began; nothing was run")
    default = Path("out") / (study.name + ("-quick" if args.quick else ""))  # type: ignore[attr-defined]
    settings = settings.replace(out=args.out or default)
    try:
        with usage_errors():
            check_study(study, settings)  # before anything runs: what is wrong with the file, in one line
        with usage_errors(CommandError):
            return run_command(study, settings, f"study {study.name}")  # type: ignore[arg-type, attr-defined]
    except UsageError:
        raise
    except Exception as e:
        own = [f for f in traceback.extract_tb(e.__traceback__) if Path(f.filename).resolve() == args.file.resolve()]
        if not own:  # not the file's own code that failed: neurowalk's traceback, whole
            raise
        return _own_failure(study, settings, args.file, own, e)


def _own_failure(study: Any, settings: Any, file: Path, own: list[traceback.FrameSummary], e: Exception) -> int:
    """A failure in the study file's own code: its frames of the traceback (not neurowalk's), then one line saying
    which runs are kept for the next try; exit status 1."""
    from neurowalk.experiments.command import kept_words
    from neurowalk.experiments.study import kept_runs

    print("Traceback (the study file's own frames):", file=sys.stderr)
    print("".join(traceback.format_list(own)) + "".join(traceback.format_exception_only(e)).rstrip(), file=sys.stderr)
    kept = kept_words(kept_runs(study, settings))
    return failed(f"neurowalk: study {study.name} failed in {file} ({type(e).__name__}); {kept}")
