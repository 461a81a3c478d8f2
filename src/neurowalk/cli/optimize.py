"""The `optimize` command: CMA-ES over the learning parameters on the surrogate (resumable)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from neurowalk.cli.common import (
    UsageError,
    backend_args,
    check_address,
    count_args,
    counts_given,
    failed,
    option_args,
    stopped,
)
from neurowalk.runners.stopping import deferred

_SIZES = (
    ("population", "candidates per generation (full 8, quick 6)"),
    ("generations", "generations (full 12, quick 5)"),
    ("environments", "training environments (full 80, quick 16)"),
    ("heldout", "held-out environments (full 200, quick 50)"),
    ("steps", "control steps per environment (full 20000, quick 10000)"),
    ("deadend-seeds", "seeds per dead-end geometry (full 3, quick 2)"),
)


def add_optimize_parser(sub: argparse._SubParsersAction) -> None:
    """The `optimize` subcommand."""
    o = sub.add_parser(
        "optimize",
        help="CMA-ES over the learning parameters on the surrogate: writes DIR/best.json, "
        "heldout.json, convergence.png (resumable)",
    )
    o.add_argument("--out", type=Path, default=Path("out/optimize"), help="output folder (default out/optimize)")
    o.add_argument("--quick", action="store_true", help="small search (6 x 5 candidates, 16 environments, 10000 steps)")
    o.add_argument("--variant", default="original", help="base variant: {optimize_bases} (default original)")
    o.add_argument(
        "--fields",
        default=None,
        metavar="NAME[,NAME...]",
        help="SensoryParams fields to search (default mu_b,mu_q,gamma_b,gamma_q,k)",
    )
    param_help = "bounds of a field (adds it to the search), e.g. mu_b=0.001:0.03; repeatable"
    option_args(o, "--param", "FIELD=LO:HI", param_help)
    count_args(o, _SIZES)
    o.add_argument("--seed", type=int, default=0, help="CMA-ES seed (default 0)")
    o.add_argument(
        "--train-seed", type=int, default=1000, help="table seed of the training environments (default 1000)"
    )
    o.add_argument("--heldout-seed", type=int, default=0, help="table seed of the held-out environments (0)")
    o.add_argument("--sigma0", type=float, default=0.2, help="initial step size in the normalised space (default 0.2)")
    backend_args(o)
    o.add_argument("--quiet", action="store_true", help="no progress bar, nor the note while the kernels compile")


def cmd_optimize(args: argparse.Namespace) -> int:
    """`neurowalk optimize`: CMA-ES over the learning parameters (resumable).

    The first SIGINT or SIGTERM stops it (exit 130, or 143 for SIGTERM) with one line saying what its folder holds.
    """
    return stopped(lambda: _optimize(args), lambda: _optimize_kept(args.out))


def _optimize_kept(out: Path) -> str:
    """The line of an interrupted search: the finished runs in its store and whether its state is saved (read from
    the files)."""
    from neurowalk.experiments.optimize.settings import STATE_FILE
    from neurowalk.fingerprint import code
    from neurowalk.runners.store import count_finished

    runs, state = count_finished(out / "results.sqlite", code=code()), out / STATE_FILE
    if not runs and not state.is_file():
        return "neurowalk: optimize interrupted before any run finished; nothing is kept"
    kept = f"{runs} finished runs are kept in {out / 'results.sqlite'}"
    if state.is_file():
        kept += f", and the search state after its last finished generation in {state}"
    return f"neurowalk: optimize interrupted: {kept}; run the same command again to resume"


def _optimize(args: argparse.Namespace) -> int:
    with deferred():  # the simulation's modules (numba's, MuJoCo's) load whole: a signal waits for their end
        import neurowalk.runners.sweep  # noqa: F401
    from neurowalk.experiments.cma_record import CmaMissingError
    from neurowalk.experiments.optimize import search as optimize
    from neurowalk.experiments.optimize.space import parse_bounds
    from neurowalk.runners import ray_backend

    check_address(args)
    fields = None if args.fields is None else [f.strip() for f in args.fields.split(",")]
    t0 = time.perf_counter()
    try:
        if args.backend == "ray":
            ray_backend.import_ray()
        bounds = dict(parse_bounds(p) for p in args.param)
        optimize.run(
            out=args.out,
            quick=args.quick,
            variant=args.variant,
            fields=fields,
            bounds=bounds,
            sizes=counts_given(args, _SIZES),
            seed=args.seed,
            train_seed=args.train_seed,
            heldout_seed=args.heldout_seed,
            sigma0=args.sigma0,
            backend=args.backend,
            workers=args.workers,
            address=args.address,
            progress=not args.quiet,
            log=lambda line: print(line, flush=True),
        )
    except (ValueError, ray_backend.RayMissingError, ray_backend.RayStartError, CmaMissingError) as e:
        raise UsageError(str(e)) from None
    except RuntimeError as e:
        return failed(f"neurowalk: optimize: {e}")
    print(f"optimize: done in {time.perf_counter() - t0:.1f} s")
    return 0
