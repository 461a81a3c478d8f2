"""Where a lock-step world-step's time goes on ``mujoco.batch``: the host's part (sensor model and noise,
controllers, recording) and the physics', in microseconds per world and control step, by number of worlds.

The host's part is the code MuJoCo Warp's engine shares (sim/lockstep.py), so on a GPU it is what stays on the CPU.
Worlds: the plastic network in one ``box`` arena, each world its own seed (one shared model: 16,384 worlds fit),
on ``--threads`` threads; ``--steps`` timed control steps after one untimed run (:func:`neurowalk.experiments.bench.
lockstep_rates`).

Run: ``python benchmarks/bench_lockstep_host.py [--worlds 64,256,1024,4096,16384] [--steps 10] [--threads 2]
[--out docs/benchmarks/lockstep_host.json]``.
"""

from __future__ import annotations

import argparse
import os
import platform
from pathlib import Path

from neurowalk.experiments.bench import lockstep_rates
from neurowalk.fileio import write_json

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--worlds", default="64,256,1024,4096,16384")
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "benchmarks" / "lockstep_host.json")
    args = ap.parse_args()
    worlds = tuple(int(w) for w in args.worlds.split(","))
    r = lockstep_rates(worlds, args.steps, engine="mujoco.batch", threads=args.threads, arena="box")
    r.update(cores=os.cpu_count(), machine=f"{platform.system()} {platform.machine()}")
    write_json(args.out, r)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
