"""A study file read, and checked before anything runs: :func:`load_study` and :func:`check_study`.

As Gymnasium's ``check_env`` tells the author of an environment what breaks its contract, :func:`check_study` tells
the author of a study file what is wrong with it, in one line naming the file and the line where it can: a syntax
error, an error while the file runs (an undefined name at module level, a failed import), no study or several, a
part that is not a function of the right arguments, ``runs`` yielding anything but a :class:`Plan` of an
``EpisodeConfig``. ``neurowalk study FILE.py`` checks the file so before it runs anything (exit status 2).
"""

from __future__ import annotations

import inspect
from collections.abc import Hashable
from pathlib import Path
from typing import Any

from neurowalk.experiments.study import Plan, Settings, Study, resolve
from neurowalk.fileio import load_python_file
from neurowalk.sim.config import EpisodeConfig

#: Each part of a study, with the arguments it is called with.
PARTS = {"runs": ("settings",), "measure": ("settings", "runs"), "plot": ("result",)}


class StudyFileError(ValueError):
    """What is wrong with a study file, in one line: ``FILE, line N: what``."""


def load_study(path: Path | str) -> Study:
    """The :class:`Study` a Python file defines (its variable ``study``, or its only Study). The file runs as a module
    (it is the user's own code); :class:`StudyFileError` (a ValueError) in one line naming the file, and the line of
    the file where it failed, where it cannot be read, does not run, or defines none."""
    path = Path(path)
    if not path.is_file():
        raise StudyFileError(f"no study file {str(path)!r}")
    module = load_python_file(path, "neurowalk_study_", StudyFileError)
    found = [v for v in vars(module).values() if isinstance(v, Study)]
    chosen = getattr(module, "study", None)
    if isinstance(chosen, Study):
        return chosen
    if len(found) != 1:
        raise StudyFileError(f"{path} defines {len(found)} studies; name the one to run `study`")
    return found[0]


def check_study(study: Study | Path | str, settings: Settings | None = None) -> Study:
    """The study (read from its file where given a path), checked: each part a function of its arguments, and
    ``runs`` with ``settings`` (default: quick) yielding :class:`Plan` s of an EpisodeConfig with hashable labels.
    :class:`StudyFileError` in one line naming what is wrong (and the study file's line, where known); an error the
    study's own ``runs`` raises comes as it is."""
    if not isinstance(study, Study):
        study = load_study(study)
    for part, args in PARTS.items():
        fn = getattr(study, part)
        if not callable(fn):
            raise StudyFileError(f"study {study.name!r}: {part} must be a function, got {type(fn).__name__}")
        if not _takes(fn, len(args)):
            raise StudyFileError(f"study {study.name!r}: {part} must take {len(args)} argument(s) ({', '.join(args)})")
    settings = settings if settings is not None else Settings(quick=True)
    study.check(settings)
    for k, plan in enumerate(study.runs(resolve(study, settings))):
        what = f"study {study.name!r}: run {k} of runs(settings)"
        if not isinstance(plan, Plan):
            hint = " (write `yield Plan(label, config)`)" if isinstance(plan, tuple) else ""
            raise StudyFileError(f"{what} is a {type(plan).__name__}, not a Plan{hint}")
        if not isinstance(plan.config, EpisodeConfig):
            raise StudyFileError(f"{what}: its config is a {type(plan.config).__name__}, not an EpisodeConfig")
        if not isinstance(plan.label, Hashable):
            raise StudyFileError(f"{what}: its label {plan.label!r} is not hashable (a string or a tuple is)")
    return study


def _takes(fn: Any, n: int) -> bool:
    """Whether ``fn`` can be called with ``n`` positional arguments (True where its signature cannot be read)."""
    try:
        inspect.signature(fn).bind(*range(n))
    except TypeError:
        return False
    except ValueError:  # a builtin without a signature
        return True
    return True
