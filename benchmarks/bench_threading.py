"""numba's threading layers under load: the vectorised environment on 1 and 2 fixed threads, each layer with 0, 1
and 2 other processes spinning on the cores (``neurowalk.experiments.bench.busy_core``), every setting in a process
of its own (the layer is chosen once per process).

Why neurowalk runs its parallel kernels on ``workqueue`` (``neurowalk/compiled.py``): with the machine shared, two
OpenMP threads (numba's default) are slower than one. Reported: steps/s (medians of ``--repeats`` alternating
measurements of ``--steps`` steps, 1024 copies) and the ratio of 2 threads to 1. Run: ``python
benchmarks/bench_threading.py [--out out/bench]``; writes ``threading.json``.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np


def child(hogs: int, steps: int, repeats: int, copies: int) -> dict:
    """In this process (its layer set by NUMBA_THREADING_LAYER): steps/s on 1 and 2 threads with ``hogs`` hogs."""
    import numba

    from neurowalk.envs.vector import ExploreVectorEnv
    from neurowalk.experiments.bench import busy_core

    env = ExploreVectorEnv(copies, max_steps=10**7)
    env.reset(seed=0)
    acts = np.random.default_rng(1).uniform(-1, 1, size=(64, copies, 2))
    for n in (1, 2):  # compile, start the threads
        numba.set_num_threads(n)
        env.step(acts[0])
    rates: dict[int, list[float]] = {1: [], 2: []}
    with contextlib.ExitStack() as stack:
        for _ in range(hogs):
            stack.enter_context(busy_core())
        for _ in range(repeats):
            for n in (1, 2, 2, 1):
                numba.set_num_threads(n)
                t0 = time.perf_counter()
                for k in range(steps):
                    env.step(acts[k % 64])
                rates[n].append(copies * steps / (time.perf_counter() - t0))
    one, two = float(np.median(rates[1])), float(np.median(rates[2]))
    return {"layer": numba.threading_layer(), "hogs": hogs, "steps_per_s_1_thread": one,
            "steps_per_s_2_threads": two, "two_over_one": two / one}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--copies", type=int, default=1024)
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    ap.add_argument("--child", type=int, default=None, help=argparse.SUPPRESS)  # hogs, in a child process
    args = ap.parse_args()
    if args.child is not None:
        print(json.dumps(child(args.child, args.steps, args.repeats, args.copies)))
        return
    rows = []
    for layer in ("omp", "workqueue"):
        for hogs in (0, 1, 2):
            cmd = [sys.executable, __file__, "--child", str(hogs), "--steps", str(args.steps), "--repeats",
                   str(args.repeats), "--copies", str(args.copies)]  # fmt: skip
            env = {**os.environ, "NUMBA_THREADING_LAYER": layer}
            row = json.loads(subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout)
            rows.append(row)
            print(f"{row['layer']:9s} {hogs} busy cores: 1 thread {row['steps_per_s_1_thread']:,.0f} steps/s, 2 "
                  f"threads {row['steps_per_s_2_threads']:,.0f} ({row['two_over_one']:.2f}x)", flush=True)  # fmt: skip
    args.out.mkdir(parents=True, exist_ok=True)
    result = {
        "cores": os.cpu_count(),
        "copies": args.copies,
        "steps": args.steps,
        "repeats": args.repeats,
        "rows": rows,
    }
    (args.out / "threading.json").write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {args.out / 'threading.json'}")


if __name__ == "__main__":
    main()
