"""The `sweep` command: many runs (a grid, or a specs file) into a resumable result store."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from neurowalk.cli.common import (
    UsageError,
    backend_args,
    check_address,
    check_engine,
    control_hz_arg,
    engine_args,
    machine_memory,
    option_args,
    out_folder,
    parse_arena_opts,
    parse_variant,
    stop_line,
    usage_errors,
    variant_args,
)
from neurowalk.fileio import write_json
from neurowalk.runners.stopping import deferred, interrupted, stop_requested

if TYPE_CHECKING:
    from neurowalk.runners.store import ResultStore
    from neurowalk.runners.sweep import SweepReport
    from neurowalk.sim.engine_interface import EngineOptions


def add_sweep_parser(sub: argparse._SubParsersAction) -> None:
    """The `sweep` subcommand."""
    s = sub.add_parser("sweep", help="many runs (a grid, or specs from a file), resumable, into DIR/results.sqlite")
    s.add_argument("--arena", default=None, metavar="NAME[,NAME...]", help="arenas: {arenas} (default open)")
    s.add_argument(
        "--controller", default=None, metavar="NAME[,NAME...]", help="controllers: {controllers} (default plastic)"
    )
    s.add_argument("--body", default=None, metavar="NAME[,NAME...]", help="bodies: {bodies} (default amosii)")
    s.add_argument("--seeds", type=int, default=None, help="seeds per condition (default 1)")
    s.add_argument("--seed-start", type=int, default=None, help="first seed (default 0): seeds S, S+1, ...")
    s.add_argument("--steps", type=int, default=None, help="control steps per run (default 1000)")
    control_hz_arg(s, default=None, metavar="HZ[,HZ...]")
    axis = "a comma list adds a grid axis (repeatable)"
    option_args(s, "--arena-opt", "KEY=V1[,V2...]", f"arena option; {axis}")
    option_args(s, "--body-opt", "KEY=V1[,V2...]", f"body option (see `neurowalk bodies`); {axis}")
    s.add_argument(
        "--specs",
        type=Path,
        default=None,
        metavar="FILE.jsonl",
        help="one run spec (JSON object of EpisodeConfig fields) per line, instead of the grid",
    )
    backend_args(s)
    s.add_argument(
        "--retries",
        type=int,
        default=3,
        metavar="N",
        help="run a job whose worker died (its process killed, its Ray node lost) up to N more times, as Ray's own "
        "tasks do (default 3; 0: store it as failed at once)",
    )
    s.add_argument("--gait", default=None, metavar="NAME[,NAME...]", help="gaits: {gaits} (default wave)")
    s.add_argument(
        "--out",
        type=Path,
        default=Path("out/sweep"),
        help="output folder: the result store, resumed where it holds runs (default out/sweep)",
    )
    s.add_argument("--export", choices=("parquet", "csv"), default=None, help="also write DIR/results.parquet|csv")
    s.add_argument("--quiet", action="store_true", help="no progress bar, nor the note while the kernels compile")
    variant_args(s, many=True)
    engine_args(s)


#: The most runs one sweep takes: every run's spec is held in memory (about 1 KB) and checked and keyed (about
#: 0.5 ms) before the first run starts, and is a row of the store.
MAX_RUNS = 1_000_000
#: Memory a sweep's run holds per control step: it keeps its whole trajectory until it ends (about 1 KB a step,
#: the physics and the planar bodies alike).
RUN_BYTES_PER_STEP = 1000
#: The largest specs file read (a spec is a line of about 100 bytes).
MAX_SPECS_BYTES = 256 * 2**20

_GRID_FLAGS = (
    "arena",
    "controller",
    "body",
    "seeds",
    "seed_start",
    "steps",
    "control_hz",
    "arena_opt",
    "body_opt",
    "variant",
    "params",
    "gait",
)


def _file_specs(args: argparse.Namespace) -> list[dict]:
    """The run specs of the --specs file (which no grid option goes with)."""
    from neurowalk.runners.specs import read_jsonl
    from neurowalk.sim.config import DEFAULT_ENGINE

    given = [f"--{f.replace('_', '-')}" for f in _GRID_FLAGS if getattr(args, f) not in (None, [])]
    given += ["--engine"] if args.engine != DEFAULT_ENGINE else []  # a spec names its own engine
    if given:
        raise UsageError(f"--specs replaces the grid options; drop {', '.join(given)}")
    size = args.specs.stat().st_size if args.specs.is_file() else 0
    if size > MAX_SPECS_BYTES:
        raise UsageError(
            f"specs file {str(args.specs)!r} holds {size / 2**20:,.0f} MiB, more than a sweep reads "
            f"({MAX_SPECS_BYTES / 2**20:,.0f} MiB); split it into several sweeps"
        )
    with usage_errors():
        specs = read_jsonl(args.specs)
    if not specs:
        raise UsageError(f"no run specs in {str(args.specs)!r}")
    _check_runs(len(specs), f"specs file {str(args.specs)!r} holds")
    return specs


def _names(flag: str, text: str) -> list[str]:
    """The names of the comma list ``text`` of ``--flag``, stripped; UsageError where one is empty."""
    names = [v.strip() for v in text.split(",")]
    if not all(names):
        raise UsageError(f"--{flag} expects NAME[,NAME...], got {text!r}")
    return names


def _sweep_specs(args: argparse.Namespace) -> list[dict]:
    """The run specs of `neurowalk sweep`: from --specs, or the grid of the other options."""
    from neurowalk.runners.specs import grid

    if args.specs is not None:
        return _file_specs(args)
    seeds, start = args.seeds if args.seeds is not None else 1, args.seed_start or 0
    if seeds < 1:
        raise UsageError(f"--seeds must be >= 1, got {seeds}")
    if start < 0:
        raise UsageError(f"--seed-start must be >= 0, got {start}")
    if start + seeds > 2**63:
        raise UsageError(f"--seed-start {start} + --seeds {seeds}: run seeds must stay below 2**63")
    axes: dict[str, list] = {}
    for flag, default in (("arena", "open"), ("controller", "plastic"), ("body", "amosii")):
        axes[flag] = _names(flag, default if getattr(args, flag) is None else getattr(args, flag))
    for what, items in (("arena", args.arena_opt), ("body", args.body_opt)):
        for key, values in parse_arena_opts(items, f"--{what}-opt").items():
            axes[f"{what}_opts.{key}"] = values.split(",")
    base: dict = {} if args.steps is None else {"steps": args.steps}
    base["engine"] = args.engine  # the canonical spec leaves the default out
    variants = _names("variant", args.variant) if args.variant is not None else []
    if args.params is not None:  # the file's own base variant unless --variant names others
        file_variant, base["params"] = parse_variant(argparse.Namespace(variant=None, params=args.params))
        variants = variants or [file_variant]
    if variants:
        axes["variant"] = variants
    if args.control_hz is not None:
        try:
            axes["control_hz"] = [float(v) for v in args.control_hz.split(",")]
        except ValueError:
            raise UsageError(f"--control-hz expects HZ[,HZ...], got {args.control_hz!r}") from None
    if args.gait is not None:
        axes["gait"] = _names("gait", args.gait)
    _check_runs(math.prod(len(v) for v in axes.values()) * seeds, "the grid has")  # before it is built
    axes["seed"] = list(range(start, start + seeds))
    return grid(base, **axes)


def _check_runs(runs: int, what: str) -> None:
    """UsageError where a sweep of ``runs`` runs is more than one sweep takes (:data:`MAX_RUNS`)."""
    if runs > MAX_RUNS:
        raise UsageError(
            f"{what} {runs:,} runs, more than one sweep takes ({MAX_RUNS:,}: every run's spec is held in "
            "memory and checked before the first run); use fewer --seeds or split the work into several "
            "sweeps"
        )


def _check_memory(specs: list[dict], workers: int) -> None:
    """UsageError where the longest run, on every worker at once, needs more memory than this machine has."""
    from neurowalk.sim.config import EpisodeConfig

    steps = max(int(float(s.get("steps", EpisodeConfig.steps))) for s in specs)  # checked whole numbers
    need, have = steps * RUN_BYTES_PER_STEP * workers, machine_memory()
    if have is not None and need > have:
        raise UsageError(
            f"runs of {steps:,} steps: a sweep's run keeps its trajectory in memory (about "
            f"{RUN_BYTES_PER_STEP:,} bytes a step), so {workers} at once need {need / 1e9:,.1f} GB, more "
            f"than this machine's {have / 1e9:,.1f} GB; use fewer --steps or --workers"
        )


def cmd_sweep(args: argparse.Namespace) -> int:
    """`neurowalk sweep`: every run spec into DIR/results.sqlite (skipping the ones done), DIR/sweep.json.

    The first SIGINT or SIGTERM stops it (exit 130, or 143 for SIGTERM) with one line saying how many of its runs are
    in the store.
    """
    opened = None
    try:
        # Loading the modules (numba's, MuJoCo's: a KeyboardInterrupt inside a C extension's import can come out as
        # an ImportError), checking the input and opening the store are short: a signal waits for their end.
        with deferred():
            opened = _open(args)
    except (KeyboardInterrupt, Exception) as e:
        if not interrupted(e):
            raise
    if stop_requested() or opened is None:
        if opened is not None:
            opened[3].close()
        return stop_line("neurowalk: sweep interrupted before its first run; nothing was run")
    return _sweep(args, *opened)


def _open(args: argparse.Namespace) -> tuple[list[dict], Path, dict, ResultStore, EngineOptions]:
    """Check the input and open the store: (specs, output folder, sweep.json's content, the store)."""
    import importlib.util

    from neurowalk.runners import ray_backend
    from neurowalk.runners.specs import check_specs, code_of, spec_key
    from neurowalk.runners.store import ResultStore, StoreError

    if args.retries < 0:
        raise UsageError(f"--retries must be >= 0, got {args.retries}")
    check_address(args)
    specs = _sweep_specs(args)
    with usage_errors(ValueError, ray_backend.RayMissingError):
        check_specs(specs)  # every bad name or value exits here, before any work
        _check_memory(specs, args.workers if args.address is None else 1)
        if args.backend == "ray":
            ray_backend.import_ray()  # a missing ray is bad input; a broken ray install raises as it is
    named = [sp["engine"] for sp in specs if isinstance(sp, dict) and isinstance(sp.get("engine"), str)]
    options = check_engine(args, named)  # a --specs file's own engines
    if args.export == "parquet" and importlib.util.find_spec("pyarrow") is None:
        raise UsageError("--export parquet needs `pip install -e '.[parquet]'` in neurowalk's folder")
    import neurowalk.runners.sweep  # noqa: F401  (here, with the signals held: it loads the simulation's modules)
    from neurowalk.sim.config import EpisodeConfig

    out = out_folder(args.out)
    settings = {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items() if k != "command"}
    info: dict = {"command": "sweep", "settings": settings, "finished": False}
    with usage_errors(StoreError):
        store = ResultStore(out / "results.sqlite", code_of(EpisodeConfig.from_spec(sp) for sp in specs))
    if not args.quiet and (line := store.other_code_line({spec_key(sp) for sp in specs}, "sweep")):
        print(line)
    return specs, out, info, store, options


def _sweep(
    args: argparse.Namespace, specs: list[dict], out: Path, info: dict, store: ResultStore, options: EngineOptions
) -> int:
    from neurowalk.runners import ray_backend
    from neurowalk.runners.sweep import SweepReport, run_sweep

    with store:
        try:
            with deferred():
                write_json(out / "sweep.json", info)
            report = run_sweep(
                specs,
                store,
                backend=args.backend,
                workers=args.workers,
                address=args.address,
                progress=not args.quiet,
                retries=args.retries,
                options=options,
            )
        except ray_backend.RayStartError as e:
            raise UsageError(str(e)) from None
        except KeyboardInterrupt:  # after the store's opening, before the sweep began
            report = SweepReport(interrupted=True)
        interrupted = report.interrupted
        try:
            with deferred():  # the files and lines below agree with the store, whenever a signal comes
                _wrap_up(args, store, report, info, out)
        except KeyboardInterrupt:  # came during the wrap-up (held to its end): stop as if it came a moment earlier
            interrupted = True
        if interrupted:
            with deferred():
                line = _kept(specs, store, out)
    if interrupted:
        return stop_line(line)
    return 1 if report.error else 0


def _wrap_up(args: argparse.Namespace, store: ResultStore, r: SweepReport, info: dict, out: Path) -> None:
    """Write the export and DIR/sweep.json; print the failures and the summary."""
    written = [out / "results.sqlite", out / "sweep.json"]
    if args.export and not r.interrupted:
        written.append(store.export(out / f"results.{args.export}", args.export))
    failures = [{"key": f.key, "spec": f.spec, "error": f.error} for f in r.failures]
    info.update(finished=not r.interrupted, counts=r.counts(), store=store.counts(), failures=failures)
    write_json(out / "sweep.json", info)
    for f in r.failures[:50]:
        print(f"neurowalk: run failed: {f.line()}", file=sys.stderr)
    if len(r.failures) > 50:
        print(
            f"neurowalk: ... and {len(r.failures) - 50} more failed runs (all in {out / 'sweep.json'})", file=sys.stderr
        )
    if r.unique:
        again = f"; run the same command again to run the {r.error} failed again" if r.error else ""
        print(
            f"sweep: {r.unique} runs: {r.skipped} already done, {r.ok} ok, {r.error} failed, in "
            f"{r.wall_time_s:.1f} s; wrote {', '.join(str(p) for p in written)}{again}"
        )


def _kept(specs: list[dict], store: ResultStore, out: Path) -> str:
    """The line of an interrupted sweep: how many of its runs the store holds (read from the store)."""
    from neurowalk.runners.sweep import prepare

    keys = [k for k, _ in prepare(specs)[0]]
    done = store.done_keys()
    have = sum(k in done for k in keys)
    left = f"run the same command again to do the other {len(keys) - have}" if have < len(keys) else "none is left"
    return (
        f"neurowalk: sweep interrupted: {have} of its {len(keys)} runs are done and kept in "
        f"{out / 'results.sqlite'}; {left}"
    )
