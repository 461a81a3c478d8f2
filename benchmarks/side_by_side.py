"""Two checkouts side by side in one run: the loop's speed before and after a change, interleaved.

Measures, for the checkout ``--before`` (a source folder: ``git worktree add DIR REV``) and this one, control steps
per second of

* ``closed_loop``: the AMOSII closed loop on the CPU (``run_episode``, the box arena, ``--physics-steps`` steps);
* ``surrogate_table2``: the planar surrogate's runs of Table 2's environments (``--table2-envs`` of them,
  ``--table2-steps`` steps each: the figure's runs, one process);
* ``vector_env``: ``neurowalk/Explore-v0`` vectorised (``--copies`` copies, ``--vector-steps`` calls of ``step``);
* ``physics_vector_env``: ``neurowalk/ExplorePhysics-v0`` vectorised (8 copies, ``--physics-env-steps`` calls).

Each measurement runs in a fresh interpreter of that checkout (``PYTHONPATH=CHECKOUT/src``) that first runs the
same work once untimed (its kernels compiled or loaded from its own numba cache), then times it. The sides
alternate (ABBA over ``--repeats`` rounds), so a drift of the machine's speed falls on both alike; reported: each
side's median, the ratio after / before of the medians, and every repeat. Run:
``python benchmarks/side_by_side.py --before /tmp/before --out docs/benchmarks/side_by_side.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]

#: name -> Python source that prints the control steps (of all copies) per second of one timed repetition.
MEASURES = {
    "closed_loop": """
import time
from neurowalk import EpisodeConfig, run_episode
cfg = EpisodeConfig(arena="box", steps={physics_steps}, seed=1)
run_episode(cfg)
t = time.perf_counter(); run_episode(cfg); print({physics_steps} / (time.perf_counter() - t))
""",
    "surrogate_table2": """
import time
from neurowalk import run_episode
from neurowalk.sim.table2 import table2_config
cfgs = [table2_config(i, body="surrogate", steps={table2_steps}) for i in range({table2_envs})]
for c in cfgs: run_episode(c)
t = time.perf_counter()
for c in cfgs: run_episode(c)
print({table2_envs} * {table2_steps} / (time.perf_counter() - t))
""",
    "vector_env": """
import time
import numpy as np
from neurowalk.envs.vector import ExploreVectorEnv
env = ExploreVectorEnv(num_envs={copies}, max_steps=10**9)
acts = np.random.default_rng(0).uniform(-1, 1, ({vector_steps}, {copies}, 2))
for rep in range(2):
    env.reset(seed=0)
    t = time.perf_counter()
    for a in acts: env.step(a)
    dt = time.perf_counter() - t
print({copies} * {vector_steps} / dt)
""",
    "physics_vector_env": """
import time
import numpy as np
from neurowalk.envs.physics_vector import ExplorePhysicsVectorEnv
env = ExplorePhysicsVectorEnv(num_envs=8, max_steps=10**9)
acts = np.random.default_rng(0).uniform(-1, 1, ({physics_env_steps}, 8, 2))
for rep in range(2):
    env.reset(seed=0)
    t = time.perf_counter()
    for a in acts: env.step(a)
    dt = time.perf_counter() - t
print(8 * {physics_env_steps} / dt)
""",
}


def measure(checkout: Path, code: str, cache: Path) -> float:
    """One timed repetition of ``code`` in a fresh interpreter of ``checkout``: control steps per second."""
    env = {**os.environ, "PYTHONPATH": str(checkout / "src"), "NUMBA_CACHE_DIR": str(cache)}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", type=Path, required=True, help="the other checkout (its src/ is imported)")
    ap.add_argument("--after", type=Path, default=HERE, help="this checkout (default)")
    ap.add_argument("--repeats", type=int, default=4)
    ap.add_argument("--physics-steps", type=int, default=1500)
    ap.add_argument("--table2-envs", type=int, default=10)
    ap.add_argument("--table2-steps", type=int, default=20000)
    ap.add_argument("--copies", type=int, default=256)
    ap.add_argument("--vector-steps", type=int, default=400)
    ap.add_argument("--physics-env-steps", type=int, default=150)
    ap.add_argument("--only", nargs="*", default=list(MEASURES))
    ap.add_argument("--out", type=Path, default=Path("out/bench/side_by_side.json"))
    args = ap.parse_args()
    sizes = {k: getattr(args, k) for k in ("physics_steps", "table2_envs", "table2_steps", "copies", "vector_steps",
                                            "physics_env_steps")}  # fmt: skip
    sides = {"before": args.before.resolve(), "after": args.after.resolve()}
    report: dict[str, object] = {
        "sizes": sizes,
        "repeats": args.repeats,
        "checkouts": {k: str(v) for k, v in sides.items()},
    }
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.only:
            code = MEASURES[name].format(**sizes)
            rates: dict[str, list[float]] = {"before": [], "after": []}
            for r in range(args.repeats):
                for side in ("before", "after") if r % 2 == 0 else ("after", "before"):
                    rates[side].append(measure(sides[side], code, Path(tmp) / side))
            med = {side: statistics.median(v) for side, v in rates.items()}
            report[name] = {
                "control_steps_per_s_before": med["before"],
                "control_steps_per_s_after": med["after"],
                "ratio_after_over_before": med["after"] / med["before"],
                "repeats": rates,
            }
            print(f"{name:20s} before {med['before']:12.0f}  after {med['after']:12.0f}  "
                  f"ratio {med['after'] / med['before']:.3f}", flush=True)  # fmt: skip
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
