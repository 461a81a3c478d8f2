"""Cost of the neural controller per control step, side by side with baselines in the same run.

Run: ``python benchmarks/bench_neural.py [--out out/bench]``. Prints a table and writes
``neural.json``. Each figure is the median over repeats of the mean cost of a batch of calls.
Baselines: an empty Python method call (interpreter speed) and ``np.tanh`` on a (2,) array (the
cheapest numpy operation), so the ratios carry over between machines.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from neurowalk.controller import NeuralController
from neurowalk.neural.motor import LocomotionNetwork
from neurowalk.neural.sensory import SensoryNetwork
from neurowalk.observation import Observation


def median_cost_us(fn: Callable[[], object], batch: int = 2000, repeats: int = 31) -> float:
    """Median over ``repeats`` of the mean cost of ``fn()`` over ``batch`` calls, in µs."""
    for _ in range(batch):  # warm up (compilation, caches)
        fn()
    costs = []
    for _ in range(repeats):
        t0 = time.perf_counter_ns()
        for _ in range(batch):
            fn()
        costs.append((time.perf_counter_ns() - t0) / batch / 1e3)
    return float(np.median(costs))


class _Noop:
    def step(self) -> None:
        return None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()

    ctrl = NeuralController("plastic")
    obs_near = Observation(us_distance=np.array([0.2, np.inf]))
    sens = SensoryNetwork("plastic")
    loco = LocomotionNetwork()
    noop = _Noop()
    x2 = np.array([0.1, -0.2])
    rows = {
        "baseline_python_call": median_cost_us(noop.step),
        "baseline_np_tanh_2": median_cost_us(lambda: np.tanh(x2)),
        "sensory_step": median_cost_us(lambda: sens.step(0.3, -1.0)),
        "locomotion_step": median_cost_us(lambda: loco.step(-1.0, -1.0)),
        "controller_act": median_cost_us(lambda: ctrl.act(obs_near)),
    }
    report = {
        "median_cost_us": rows,
        "controller_act_over_np_tanh": rows["controller_act"] / rows["baseline_np_tanh_2"],
        "controller_act_budget_us": 50.0,
        "machine": {"python": platform.python_version(), "processor": platform.machine(), "cores": os.cpu_count()},
    }
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "neural.json").write_text(json.dumps(report, indent=2) + "\n")
    for k, v in rows.items():
        print(f"{k:24s} {v:8.2f} µs")
    print(f"controller act = {report['controller_act_over_np_tanh']:.1f} x np.tanh on 2 numbers; budget 50 µs")


if __name__ == "__main__":
    main()
