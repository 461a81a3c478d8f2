"""The flags of a study's settings (``figure`` and ``study``), made from
:class:`~neurowalk.experiments.study.Settings`, and the run of a study from the command line.

A study declares the optional settings it takes (``Study.takes``); its ``--help`` shows those only, and a flag of
another setting is refused in one line naming the ones it takes.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from neurowalk.cli.common import (
    Parser,
    UsageError,
    check_engine,
    control_hz_arg,
    engine_args,
    known,
    option_args,
    out_folder,
    parse_arena_opts,
    parse_variant,
    stop_line,
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

    p.add_argument("--out", type=Path, default=None, help="output folder (default: out/NAME)")
    p.add_argument("--quick", action="store_true", help="shorter runs, coarser grids")
    p.add_argument("--seed", type=int, default=0, help="seed of every random draw (default 0)")
    for name in OPTIONAL:
        p.hidden = takes is not None and name not in takes  # given anyway, hidden flags are refused in one line
        _add(p, name)
    p.hidden = False


def settings_of(args: argparse.Namespace, study: Study, what: str) -> Settings:
    """The settings of the command line, checked (UsageError: one line naming the value, or the flag ``study``
    does not take and the ones it does; ``what`` names it, e.g. "figure fig3"); what the study needs of them (a
    body) :func:`run_and_write` resolves, before any work."""
    from neurowalk.experiments.study import Settings, resolve

    given = _given(args)
    refused = [FLAGS[n] for n in given if n not in study.takes]
    if refused:
        takes = ", ".join(FLAGS[n] for n in study.takes) or "none but --quick, --seed and --out"
        raise UsageError(f"{what} takes no {', '.join(refused)}; it takes {takes}")
    kw: dict[str, Any] = {n: getattr(args, n) for n in ("quick", "seed", "out")}
    kw.update({n: getattr(args, n) for n in ("seeds", "climbing", "video", "control_hz", "workers") if n in given})
    if "body" in given:
        kw["body"] = known("body", args.body, "bodies")
    if "gait" in given:
        kw["gait"] = known("gait", args.gait, "gaits")
    if "variant" in given or "params" in given:
        kw["variant"], kw["params"] = parse_variant(args)
    if "engine" in given:
        kw.update(engine=args.engine, device=args.device)
    if "backend" in given:
        kw.update(backend=args.backend, address=args.address)
    if "size" in given:
        kw["size"] = _size(args.arena_opt)
    try:
        settings = Settings(**kw)
    except ValueError as e:
        flag, _, rest = str(e).partition(" must ")
        raise UsageError(f"--{flag.replace('_', '-')} must {rest}" if rest else str(e)) from None
    if "engine" in given:  # the device resolved (a GPU, or Warp's CPU device, said in one line)
        try:  # after a body the engine cannot run is refused (the note would say nothing then)
            resolve(study, settings)
        except ValueError as e:
            raise UsageError(str(e)) from None
        settings = settings.replace(device=check_engine(args).device)
    return settings


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
    """The box side of ``--arena-opt size=M`` (the only option a study takes), checked by the arena itself."""
    from neurowalk.arenas import make_arena

    opts = parse_arena_opts(items)
    if set(opts) != {"size"}:
        raise UsageError(f"--arena-opt takes size=M only, got {', '.join(items)}")
    try:
        size = float(opts["size"])
        make_arena("random", size=size, n_boxes=0)  # the arena's own range check
    except ValueError as e:
        raise UsageError(f"--arena-opt size={opts['size']}: {e}") from None
    return size


def run_and_write(study: Study, settings: Settings, what: str) -> int:
    """Compute ``study`` and write NAME.json (NAME.npz) and NAME.png into ``settings.out``, saying so in one line;
    a stop (exit 130/143) says in one line what is kept. ``what`` names it in the messages ("figure fig3")."""
    from neurowalk.experiments.study import compute, kept_runs, resolve, write
    from neurowalk.runners.stopping import interrupted
    from neurowalk.runners.store import StoreError
    from neurowalk.sim.episode import RunInterruptedError

    out = settings.out
    assert out is not None
    t0 = time.perf_counter()
    existed = out.exists()
    out_folder(out)  # the runner says where it goes on from finished runs (run_store)

    def leave_nothing() -> None:
        if not existed and not any(out.iterdir()):
            out.rmdir()  # made for this command, still empty: leave nothing behind

    try:  # what the study needs of the settings (a body that climbs, runs the engine, the rate): before any work
        settings = resolve(study, settings)
    except ValueError as e:
        leave_nothing()
        raise UsageError(str(e)) from None
    paths: dict[str, Path] = {}
    try:
        try:
            result = compute(study, settings)
        except StoreError as e:
            raise UsageError(str(e)) from None
        except ValueError as e:  # a study checks its settings before it runs (e.g. a surrogate at 27 Hz)
            leave_nothing()
            raise UsageError(f"{what}: {e}") from None
        write(study, result, out, paths)
    except (KeyboardInterrupt, Exception) as e:  # RunInterruptedError: a run in this process, stopped part-way
        if not (interrupted(e) or isinstance(e, RunInterruptedError)):
            raise
        files = ", ".join(str(paths[k]) for k in ("png", "json", "npz") if k in paths)
        if "png" in paths:
            line = f"neurowalk: {study.name} interrupted as it ended; it wrote {files}"
        elif paths:
            line = f"neurowalk: {study.name} interrupted while drawing: its numbers are in {files}; `--replot` draws it"
        else:
            line = interrupted_line(study.name, kept_runs(study, settings))
        return stop_line(line)
    files = [paths[k] for k in ("png", "json", "npz") if k in paths]
    print(f"{study.name}: wrote {', '.join(str(p) for p in files)} in {time.perf_counter() - t0:.1f} s")
    if not settings.given():  # the command the reproduction judges: its claims, where it has any
        print("\n".join(claim_lines(study.name, result.summary, settings.quick)))
    return 0


def claim_lines(name: str, summary: dict[str, Any], quick: bool) -> list[str]:
    """The results figure ``name`` judges (its study's claims, those of ``neurowalk reproduce``) from ``summary``: one
    line each (what, the paper's value, neurowalk's, the verdict) and where the rules are (none: no judged result)."""
    from neurowalk.experiments import FIGURES
    from neurowalk.experiments.reproduce.report import cell

    study = FIGURES.get(name)
    claims = study.claims(summary, quick) if study is not None and study.claims is not None else []
    if not claims:
        return []
    lines = [f"{name} against the paper{' (--quick: fewer, shorter runs)' if quick else ''}:"]
    rows = summary.get("counts")
    if isinstance(rows, dict) and all(
        isinstance(r, dict) and {"success", "environments"} <= set(r) for r in rows.values()
    ):
        lines.append("  successes: " + ", ".join(f"{k} {r['success']}/{r['environments']}" for k, r in rows.items()))
    for c in claims:
        lines.append(f"  {c.what}: paper {cell(c.paper, c.unit)}, neurowalk {cell(c.measured, c.unit)} -> {c.verdict}")
    lines.append(f"  (the rules and the full runs' verdicts: docs/results/details.md#{name})")
    return lines


def interrupted_line(name: str, kept: dict[Path, int] | None) -> str:
    """The line of a study interrupted while it ran: the finished runs ``kept`` in its result stores, by file
    (:func:`~neurowalk.experiments.study.kept_runs`; None: the study runs no episode)."""
    if kept is None:
        return f"neurowalk: {name} interrupted; it runs no episode (the network alone), so none is kept: run it again"
    if not kept:
        return f"neurowalk: {name} interrupted before any of its runs finished; nothing is kept"
    return (
        f"neurowalk: {name} interrupted: {sum(kept.values())} finished runs are kept in {_where(kept)}; run "
        "the same command again to go on from them"
    )


def kept_words(kept: dict[Path, int] | None) -> str:
    """What a failed study keeps, in words: ``61 finished runs are kept in out/gap (61 in results.sqlite): fix it and
    run the same command to go on from them``, or that none is (None: it runs no episode)."""
    if kept is None:
        return "it runs no episode: nothing is kept"
    if not kept:
        return "none of its runs had finished: nothing is kept"
    return (
        f"{sum(kept.values())} finished runs are kept in {_where(kept)}: fix it and run the same command to go on "
        "from them"
    )


def _where(kept: dict[Path, int]) -> str:
    """The stores of ``kept`` in words: ``out/fig3 (61 in results.sqlite, 4 in track.sqlite)``."""
    folders = sorted({str(p.parent) for p in kept})
    return f"{', '.join(folders)} ({', '.join(f'{n} in {p.name}' for p, n in kept.items())})"
