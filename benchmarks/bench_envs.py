"""Gymnasium environments: ``neurowalk/Explore-v0`` single against vectorised (1024 copies), in the same run.

Measures environment steps per second of

* ``single``: one :class:`~neurowalk.envs.explore.ExploreEnv`, stepped from Python (``--single-steps`` steps);
* ``vector``: :class:`~neurowalk.envs.vector.ExploreVectorEnv` with ``--copies`` copies (``gymnasium.make_vec(...,
  vectorization_mode="vector_entry_point")``), ``--vector-steps`` calls of ``step`` inside an episode;
* ``vector_with_resets``: the same through whole episodes of ``--max-steps`` steps, so that every copy's automatic
  reset (a new random environment) is counted too.

Actions are random steering pairs drawn beforehand. Reported: steps per second of each, the ratios against the
single environment, the threads numba used. Run: ``python benchmarks/bench_envs.py [--copies 1024] [--out
out/bench]``; writes ``envs.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numba
import numpy as np

from neurowalk.envs.explore import ExploreEnv
from neurowalk.envs.vector import ExploreVectorEnv


def single_rate(steps: int) -> float:
    env = ExploreEnv(max_steps=steps + 1)
    env.reset(seed=0)
    acts = np.random.default_rng(0).uniform(-1, 1, size=(steps, 2))
    env.step(acts[0])
    t0 = time.perf_counter()
    for a in acts:
        env.step(a)
    return steps / (time.perf_counter() - t0)


def vector_rate(copies: int, steps: int, max_steps: int, resets: bool) -> float:
    env = ExploreVectorEnv(copies, max_steps=max_steps)
    env.reset(seed=0)
    acts = np.random.default_rng(1).uniform(-1, 1, size=(64, copies, 2))
    env.step(acts[0])  # compile, warm
    n = max_steps + 1 if resets else steps  # a whole episode and the reset step after it
    env.reset(seed=1)
    t0 = time.perf_counter()
    for k in range(n):
        env.step(acts[k % 64])
    return copies * n / (time.perf_counter() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--copies", type=int, default=1024)
    ap.add_argument("--single-steps", type=int, default=20_000)
    ap.add_argument("--vector-steps", type=int, default=500)
    ap.add_argument("--max-steps", type=int, default=2000)
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    single = single_rate(args.single_steps)
    vector = vector_rate(args.copies, args.vector_steps, args.max_steps, resets=False)
    with_resets = vector_rate(args.copies, args.vector_steps, args.max_steps, resets=True)
    result = {"single_steps_per_s": single, "vector_steps_per_s": vector, "vector_with_resets_steps_per_s": with_resets,
              "vector_over_single": vector / single, "vector_with_resets_over_single": with_resets / single,
              "copies": args.copies, "max_steps": args.max_steps, "numba_threads": numba.config.NUMBA_NUM_THREADS,
              "cores": os.cpu_count()}  # fmt: skip
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "envs.json").write_text(json.dumps(result, indent=2) + "\n")
    print(f"single env: {single:,.0f} steps/s")
    print(
        f"vector env, {args.copies} copies: {vector:,.0f} steps/s ({vector / single:.0f}x); through whole "
        f"{args.max_steps}-step episodes with their resets: {with_resets:,.0f} steps/s ({with_resets / single:.0f}x)"
    )


if __name__ == "__main__":
    main()
