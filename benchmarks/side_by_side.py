"""Two checkouts side by side in one run: the loop's speed before and after a change, in paired rounds.

Measures, for the checkout ``--before`` (a source folder: ``git worktree add DIR REV``) and this one, control steps
per second of

* ``closed_loop``: the AMOSII closed loop on the CPU (``run_episode``, the box arena, ``--physics-steps`` steps);
* ``surrogate_table2``: the planar surrogate's runs of Table 2's environments (``--table2-envs`` of them,
  ``--table2-steps`` steps each: the figure's runs, one process);
* ``vector_env``: ``neurowalk/Explore-v0`` vectorised (``--copies`` copies, ``--vector-steps`` calls of ``step``);
* ``physics_vector_env``: ``neurowalk/ExplorePhysics-v0`` vectorised (8 copies, ``--physics-env-steps`` calls).

Each side is one interpreter of its checkout (``PYTHONPATH=CHECKOUT/src``, its own numba cache) that builds the work,
runs it once untimed (its kernels compiled or loaded), then times one repetition each time it is asked. A round asks
both sides, one after the other (ABBA order over the rounds); only one runs at a time. The machine's speed drifts
(on a shared 2-core machine up to 2x over the run: docs/benchmarks/side_by_side_paired.json's repeats), so a round's two
repetitions, seconds apart, are compared with each other: reported per measure are each side's median, the median of
the rounds' ratios after / before, and a distribution-free 95% interval of that median (order statistics of the
binomial), and every repeat. (side_by_side.json, side_by_side_long.json and side_by_side_physics_env.json in
docs/benchmarks were measured before 0cb5293: a fresh interpreter a repetition, the ratio of the two sides'
medians.) Run:
``python benchmarks/side_by_side.py --before /tmp/before --out docs/benchmarks/side_by_side.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]

#: name -> (setup, one repetition): Python source; the repetition's last expression is its control steps (of all
#: copies), as ``steps = ...``.
MEASURES = {
    "closed_loop": (
        """
from neurowalk import EpisodeConfig, run_episode
cfg = EpisodeConfig(arena="box", steps={physics_steps}, seed=1)
""",
        """
run_episode(cfg)
steps = {physics_steps}
""",
    ),
    "surrogate_table2": (
        """
from neurowalk import run_episode
from neurowalk.sim.table2 import table2_config
cfgs = [table2_config(i, body="surrogate", steps={table2_steps}) for i in range({table2_envs})]
""",
        """
for c in cfgs: run_episode(c)
steps = {table2_envs} * {table2_steps}
""",
    ),
    "vector_env": (
        """
import numpy as np
from neurowalk.envs.vector import ExploreVectorEnv
env = ExploreVectorEnv(num_envs={copies}, max_steps=10**9)
acts = np.random.default_rng(0).uniform(-1, 1, ({vector_steps}, {copies}, 2))
""",
        """
env.reset(seed=0)
for a in acts: env.step(a)
steps = {copies} * {vector_steps}
""",
    ),
    "physics_vector_env": (
        """
import numpy as np
from neurowalk.envs.physics_vector import ExplorePhysicsVectorEnv
env = ExplorePhysicsVectorEnv(num_envs=8, max_steps=10**9)
acts = np.random.default_rng(0).uniform(-1, 1, ({physics_env_steps}, 8, 2))
""",
        """
env.reset(seed=0)
for a in acts: env.step(a)
steps = 8 * {physics_env_steps}
""",
    ),
}

#: A side's interpreter: the setup, one untimed repetition, then one timed repetition per line read.
WORKER = """
import sys, time
{setup}
def repetition():
{body}
    return steps
repetition()
print("ready", flush=True)
for _ in sys.stdin:
    t = time.perf_counter()
    n = repetition()
    print(n / (time.perf_counter() - t), flush=True)
"""


class Side:
    """One checkout's interpreter, timing one repetition per :meth:`rate`."""

    def __init__(self, checkout: Path, setup: str, body: str, cache: Path) -> None:
        env = {**os.environ, "PYTHONPATH": str(checkout / "src"), "NUMBA_CACHE_DIR": str(cache)}
        code = WORKER.format(setup=setup, body="\n".join("    " + line for line in body.strip().splitlines()))
        self.proc = subprocess.Popen([sys.executable, "-c", code], env=env, text=True, stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE)  # fmt: skip
        if self._line() != "ready":
            raise RuntimeError(f"the interpreter of {checkout} did not start its measure")

    def _line(self) -> str:
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"a measuring interpreter ended (status {self.proc.wait()})")
        return line.strip()

    def rate(self) -> float:
        """Control steps per second of one timed repetition."""
        assert self.proc.stdin is not None
        self.proc.stdin.write("\n")
        self.proc.stdin.flush()
        return float(self._line())

    def close(self) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.close()
        self.proc.wait()


def median_interval(values: list[float], level: float = 0.95) -> tuple[float, float]:
    """A distribution-free interval holding the median of ``values``' population with probability >= ``level``:
    the order statistics k and n + 1 - k, k the largest with P(Binomial(n, 1/2) < k) <= (1 - level) / 2."""
    v, n = sorted(values), len(values)
    k, tail = 0, 0.0
    while k < n // 2:
        tail += math.comb(n, k) / 2**n
        if tail > (1 - level) / 2:
            break
        k += 1
    return (v[k - 1], v[n - k]) if k >= 1 else (v[0], v[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", type=Path, required=True, help="the other checkout (its src/ is imported)")
    ap.add_argument("--after", type=Path, default=HERE, help="this checkout (default)")
    ap.add_argument("--repeats", type=int, default=20, help="rounds (one repetition of each side a round)")
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
        "method": "paired rounds: one interpreter a side, one repetition of each a round, ABBA order",
    }
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.only:
            setup, body = (part.format(**sizes) for part in MEASURES[name])
            workers = {side: Side(path, setup, body, Path(tmp) / side) for side, path in sides.items()}
            rates: dict[str, list[float]] = {"before": [], "after": []}
            for r in range(args.repeats):
                for side in ("before", "after") if r % 2 == 0 else ("after", "before"):
                    rates[side].append(workers[side].rate())
            for w in workers.values():
                w.close()
            ratios = [a / b for a, b in zip(rates["after"], rates["before"], strict=True)]
            low, high = median_interval(ratios)
            report[name] = {
                "control_steps_per_s_before": statistics.median(rates["before"]),
                "control_steps_per_s_after": statistics.median(rates["after"]),
                "ratio_after_over_before": statistics.median(ratios),
                "ratio_95_interval": [low, high],
                "repeats": rates,
            }
            print(f"{name:20s} ratio {statistics.median(ratios):.3f} (95%: {low:.3f} to {high:.3f})", flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
