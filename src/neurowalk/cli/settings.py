"""The flags of a study's settings (``figure`` and ``study``), made from
:class:`~neurowalk.experiments.study.Settings`, and the settings they give: parsed once here, then only the
:class:`Settings` travel on (:func:`~neurowalk.experiments.command.run_command` checks and runs them).

A study declares the optional settings it takes (``Study.takes``); its ``--help`` shows those only, and a flag of
another setting is refused in one line naming the ones it takes.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from neurowalk.cli.common import (
    Parser,
    UsageError,
    control_hz_arg,
    engine_args,
    option_args,
    variant_args,
)

if TYPE_CHECKING:
    from neurowalk.experiments.study import Settings, Study

#: Each optional setting's flags, as the messages name them.
FLAGS = {
    "seeds": "--seeds",
    "body": "--body",
    "climbing": "--climb",
    "variant": "--variant",
    "params": "--params",
    "gait": "--gait",
    "video": "--video",
    "size": "--arena-opt size=M",
    "engine": "--engine/--device",
    "control_hz": "--control-hz",
    "workers": "--workers",
    "backend": "--backend/--address",
}


def _add(p: argparse.ArgumentParser, name: str) -> None:
    """The flags of optional setting ``name``."""
    if name == "seeds":
        p.add_argument("--seeds", type=int, default=None, help="seeds (or environments) per condition")
    elif name == "body":
        p.add_argument("--body", default=None, help="{bodies} (default per study; see `neurowalk bodies`)")
    elif name == "climbing":
        p.add_argument(
            "--climb",
            dest="climbing",
            action="store_true",
            help="leg reflexes and backbone control on",
        )
    elif name in ("variant", "params"):
        variant_args(p, only=name)
    elif name == "gait":
        p.add_argument("--gait", default=None, help="the locomotion network's gait: {gaits} (default wave)")
    elif name == "video":
        p.add_argument("--video", action="store_true", help="also write the example runs' videos")
    elif name == "size":
        option_args(p, "--arena-opt", "size=M", "box side of the random environments, m (default 1, the authors')")
    elif name == "engine":
        engine_args(p)
    elif name == "control_hz":
        control_hz_arg(p, default=None)
    elif name == "workers":
        p.add_argument("--workers", type=int, default=None, help="processes (or Ray CPUs) of the runs (default 2)")
    elif name == "backend":
        p.add_argument(
            "--backend", default="local", help="where the runs run: local (a process pool) | ray (default local)"
        )
        p.add_argument("--address", default=None, help="the Ray cluster to join (with --backend ray)")


def add_settings_args(p: Parser, takes: tuple[str, ...] | None) -> None:
    """``--out``, ``--quick``, ``--seed`` and every optional setting's flags; those of settings not in ``takes``
    (where given) are accepted but hidden from the help, and refused by :func:`settings_of`."""
    from neurowalk.experiments.study import OPTIONAL

    out_help = "output folder (default: out/NAME; out/NAME-quick with --quick)"
    p.add_argument("--out", type=Path, default=None, help=out_help)
    p.add_argument(
        "--quick",
        action="store_true",
        help="a first look: the study's quick version (fewer seeds or environments, shorter runs, as it defines), "
        "into a folder of its own (a folder holding the full result is refused)",
    )
    p.add_argument("--seed", type=int, default=0, help="seed of every random draw (default 0)")
    for name in OPTIONAL:
        p.hidden = takes is not None and name not in takes  # given anyway, hidden flags are refused in one line
        _add(p, name)
    p.hidden = False


def settings_of(args: argparse.Namespace, study: Study, what: str, **fields: Any) -> Settings:
    """The settings of the command line, parsed (UsageError: one line naming the flag ``study`` does not take and
    the ones it does, or a value that is no value of its kind; ``what`` names it, e.g. "figure 'fig3'"), with
    ``fields`` (e.g. its output folder). Whether the names they give exist, and what the study needs of them,
    :func:`~neurowalk.experiments.command.run_command` checks, before any work."""
    from neurowalk.experiments.study import Settings

    given = _given(args)
    refused = [FLAGS[n] for n in given if n not in study.takes]
    if refused:
        takes = ", ".join(FLAGS[n] for n in study.takes) or "none but --quick, --seed and --out"
        raise UsageError(f"{what} takes no {', '.join(refused)}; it takes {takes}")
    kw: dict[str, Any] = {n: getattr(args, n) for n in ("quick", "seed", "out")}
    kw.update({n: getattr(args, n) for n in ("seeds", "body", "gait", "climbing", "video", "control_hz", "workers")
               if n in given})  # fmt: skip
    if "engine" in given:
        kw.update(engine=args.engine, device=args.device)
    if "backend" in given:
        kw.update(backend=args.backend, address=args.address)
    if "size" in given:
        kw["size"] = _size(args.arena_opt)
    if "variant" in given or "params" in given:
        kw["variant"], kw["params"] = _variant(args.variant, args.params)
    kw.update(fields)
    try:
        return Settings(**kw)
    except ValueError as e:
        flag, _, rest = str(e).partition(" must ")
        raise UsageError(f"--{flag.replace('_', '-')} must {rest}" if rest else str(e)) from None


def figure_settings(args: argparse.Namespace, study: Study) -> Settings:
    """The settings of ``neurowalk figure NAME``: its flags' (out: ``out/NAME``, ``-climb``, the rate's suffix and
    ``-quick`` added where they are given), or every one from ``--settings FILE`` (:func:`settings_file`)."""
    default = Path("out") / (args.name + ("-climb" if args.climbing else "") + _rate_suffix(args.control_hz)
                             + ("-quick" if args.quick else ""))  # fmt: skip
    if args.settings_file is not None:
        return settings_file(args, study)
    return settings_of(args, study, f"figure {args.name!r}", out=args.out or default, shared_runs=args.shared_runs)


def _rate_suffix(control_hz: float | None) -> str:
    """The default output folder's suffix for a control rate: "" at the default 10 Hz, else "-27hz"."""
    if control_hz is None or control_hz == 10.0:
        return ""
    return f"-{control_hz:g}hz"


def settings_file(args: argparse.Namespace, study: Study) -> Settings:
    """The settings of ``--settings FILE`` for figure ``args.name`` (out: the file's, else ``out/NAME``), checked as
    the flags' are (those of a setting the figure does not take, where it runs); UsageError in one line naming the
    file where it cannot be read, names another figure, is given with other settings, or holds a bad value."""
    from neurowalk.experiments.output import failure_words
    from neurowalk.experiments.study import Settings

    path = args.settings_file
    if _given(args) or args.quick or args.seed or args.out or args.shared_runs is not None or args.replot:
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
        return Settings(**{"out": Path("out") / args.name, **fields})
    except (ValueError, TypeError) as e:
        raise UsageError(f"--settings {path}: {e}") from None


def _variant(variant: str | None, params: Path | None) -> tuple[str | None, Path | None]:
    """(variant, params) of --variant and --params: the params file's path, read as the settings are resolved (its
    fields, and its base variant where --variant names none)."""
    if variant is not None and not variant.strip():
        raise UsageError(f"--variant expects a name (e.g. paper, original), got {variant!r}")
    return variant, params


def _given(args: argparse.Namespace) -> list[str]:
    """The optional settings whose flags the command line gives."""
    out = [n for n in ("seeds", "body", "variant", "params", "gait", "control_hz", "workers", "address")
           if getattr(args, n, None) is not None]  # fmt: skip
    out += [n for n in ("climbing", "video") if getattr(args, n, False)]
    out += ["size"] * bool(getattr(args, "arena_opt", None))
    out += ["engine"] * (getattr(args, "engine", "mujoco") != "mujoco" or getattr(args, "device", None) is not None)
    out += ["backend"] * (getattr(args, "backend", "local") != "local" or "address" in out)
    return [n for n in dict.fromkeys(out) if n != "address"]


def _size(items: list[str]) -> float:
    """The box side of ``--arena-opt size=M`` (the only option a study takes); its range the arena checks."""
    key, _, value = items[-1].partition("=")
    if len(items) != 1 or key != "size":
        raise UsageError(f"--arena-opt takes size=M only, got {', '.join(items)}")
    try:
        return float(value)
    except ValueError:
        raise UsageError(f"--arena-opt size={value}: not a number") from None
