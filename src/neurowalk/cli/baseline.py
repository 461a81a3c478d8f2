"""The `baseline` command: learned policies (evolved RNN, PPO, recurrent PPO) against the two neurons."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from neurowalk.cli.common import count_args, counts_given, out_folder, stopped, usage_errors
from neurowalk.runners.stopping import deferred

_SIZES = (
    ("generations", "CMA-ES generations of the evolved network (full 150, quick 3)"),
    ("population", "candidates per generation (full 16, quick 6)"),
    ("envs", "training environments per generation (full 8, quick 4)"),
    ("ppo-steps", "PPO training env steps (full 5000000, quick 4096)"),
    ("rppo-steps", "recurrent PPO training env steps (full 2000000, quick 2048)"),
    ("episode-steps", "control steps of a training episode (full 10000, quick 200)"),
    ("eval-envs", "held-out environments (full 200, quick 20)"),
    ("eval-steps", "control steps per held-out environment (full 20000, quick 3000)"),
)


def add_baseline_parser(sub: argparse._SubParsersAction) -> None:
    """The `baseline` subcommand."""
    b = sub.add_parser(
        "baseline",
        help="train learned policies and score them against the networks on held-out "
        "Table 2 environments: DIR/baselines.json, .md, .png (resumable; extra rl)",
    )
    b.add_argument("--out", type=Path, default=Path("out/baseline"), help="output folder (default out/baseline)")
    b.add_argument(
        "--methods",
        default="neuroevo,ppo,rppo",
        metavar="NAME[,NAME...]",
        help="learned methods: neuroevo (CMA-ES, needs cma), ppo, rppo (need the rl extra); default all three",
    )
    b.add_argument("--quick", action="store_true", help="tiny budgets (a smoke test, not a result)")
    count_args(b, _SIZES)
    b.add_argument("--seed", type=int, default=0, help="training seed (default 0)")
    b.add_argument("--quiet", action="store_true", help="no progress bars, nor the note while the kernels compile")


def cmd_baseline(args: argparse.Namespace) -> int:
    """`neurowalk baseline`: train (resuming), score, write the table and the plot.

    The first SIGINT or SIGTERM stops it (exit 130, or 143 for SIGTERM) with one line naming the checkpoints and
    scores on disk.
    """
    return stopped(lambda: _baseline(args), lambda: kept_line(args.out))


def kept_line(out: Path) -> str:
    """The line of an interrupted baseline: its training checkpoints in ``out`` (the files) and its held-out scores
    (the policies scored, in its result store)."""
    from neurowalk.fingerprint import code
    from neurowalk.runners.store import count_finished

    files = [str(p.relative_to(out)) for p in sorted(out.glob("training/*/*")) if not p.name.startswith(".")]
    if scored := count_finished(out / "results.sqlite", code=code()):
        files.append(f"results.sqlite ({scored} policies scored)")
    if not files:
        return "neurowalk: baseline interrupted before its first checkpoint; nothing is kept"
    names = ", ".join(files)
    return f"neurowalk: baseline interrupted; kept in {out}: {names}; run the same command again to go on from them"


def _baseline(args: argparse.Namespace) -> int:
    with deferred():  # the simulation's modules (numba's) load whole: a signal waits for their end
        import neurowalk.envs.vector  # noqa: F401
    from neurowalk.experiments.baselines import comparison as baseline
    from neurowalk.experiments.baselines.ppo import RlMissingError
    from neurowalk.experiments.cma_record import CmaMissingError

    methods = [m.strip() for m in args.methods.split(",")]
    sizes = counts_given(args, _SIZES)
    t0 = time.perf_counter()
    with usage_errors(ValueError, RlMissingError, CmaMissingError):
        if not 0 <= args.seed < 2**32:
            raise ValueError(f"--seed must be in [0, 2**32), got {args.seed}")
        baseline.check_methods(methods, available=False)
        baseline.sizes_of(args.quick, sizes)
        baseline.check_methods(methods)
        out_folder(args.out)
        result = baseline.run(
            args.out,
            methods=methods,
            quick=args.quick,
            sizes=sizes,
            seed=args.seed,
            progress=not args.quiet,
            log=lambda line: print(line, flush=True),
        )
    for r in result["rows"]:
        print(f"{r['label']:>24}: {r['success']}/{r['n']} ({r['rate']:.1%}), coverage {r['coverage_mean']:.1%}")
    print(f"baseline: done in {time.perf_counter() - t0:.1f} s; wrote {args.out / 'baselines.md'}, .json, .png")
    return 0
