"""Control steps per second of the wheeled body against AMOSII, in the same run, arena and steering.

Both bodies run in the arena ``random`` drawn with seed 0, reset with seed 0, for ``--steps`` control steps of
observe, act, apply and advance (the loop of ``neurowalk.sim``, without recording):

* ``fixed`` (the headline): a constant steering ``--steer`` (default (-1, -1), forward). The wheeled body takes it
  in ``apply``; AMOSII takes the joint targets of :class:`~neurowalk.controller.FixedController` (the locomotion
  network driven by that steering).
* ``plastic``: the plastic sensory network closes the loop through
  :class:`~neurowalk.controller.NeuralController`'s compiled ``act`` (sensory and locomotion networks, as
  ``neurowalk run`` does for every body): AMOSII takes its joint targets, the wheeled body its steering (O1, O2).

Each body and loop is timed ``--repeats`` times in alternation (after one untimed warm-up run, which also compiles
the networks); the median is reported. Target of issue 17: wheeled at least 5x AMOSII's control steps per second.

Run: ``python benchmarks/bench_bodies.py [--steps 2000] [--repeats 3] [--out out/bench]``; writes ``bodies.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np

from neurowalk.arenas import make_arena
from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body.amosii import AmosII
from neurowalk.body.wheeled_body import Wheeled
from neurowalk.controller import FixedController, NeuralController

TARGET_RATIO = 5.0
"""Issue 17: the wheeled body at least this many times AMOSII's control steps per second."""


def _amosii_loop(arena: ArenaSpec, controller: FixedController | NeuralController, steps: int) -> float:
    """Wall time (s) of ``steps`` control steps of AMOSII driven by ``controller``'s joint targets."""
    body = AmosII(arena)
    body.reset(np.random.default_rng(0))
    controller.reset(np.random.default_rng(0))
    t0 = time.perf_counter()
    for _ in range(steps):
        body.apply(controller.act(body.observe()))
        body.advance()
    return time.perf_counter() - t0


def _wheeled_loop(arena: ArenaSpec, steer: np.ndarray | None, steps: int) -> float:
    """Wall time (s) of ``steps`` control steps of the wheeled body: fixed ``steer``, or the plastic network if None."""
    body = Wheeled(arena)
    body.reset(np.random.default_rng(0))
    t0 = time.perf_counter()
    if steer is not None:
        for _ in range(steps):
            body.observe()
            body.apply(steer)
            body.advance()
        return time.perf_counter() - t0
    ctrl = NeuralController("plastic")
    ctrl.reset(np.random.default_rng(0))
    for _ in range(steps):  # as the one control loop (sim/episode.py) drives a steering body
        ctrl.act(body.observe())
        body.apply(ctrl.steering)
        body.advance()
    return time.perf_counter() - t0


def _timed(runs: dict[str, Callable[[], float]], repeats: int) -> dict[str, float]:
    """Median wall time (s) of each run, the runs alternating; one untimed warm-up of each first."""
    for run in runs.values():
        run()
    times: dict[str, list[float]] = {name: [] for name in runs}
    for _ in range(repeats):
        for name, run in runs.items():
            times[name].append(run())
    return {name: float(np.median(t)) for name, t in times.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=2000, help="control steps per timed run")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs of each body and loop")
    ap.add_argument("--steer", type=float, nargs=2, default=(-1.0, -1.0), metavar=("O1", "O2"))
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    if args.steps < 1 or args.repeats < 1:
        ap.error(f"--steps and --repeats must be >= 1, got {args.steps} and {args.repeats}")
    arena = make_arena("random", rng=np.random.default_rng(0))
    steer = np.array(args.steer, dtype=float)
    n = args.steps
    wall = _timed(
        {
            "wheeled_fixed": lambda: _wheeled_loop(arena, steer, n),
            "amosii_fixed": lambda: _amosii_loop(arena, FixedController(tuple(steer)), n),
            "wheeled_plastic": lambda: _wheeled_loop(arena, None, n),
            "amosii_plastic": lambda: _amosii_loop(arena, NeuralController("plastic"), n),
        },
        args.repeats,
    )
    rate = {name: n / t for name, t in wall.items()}
    wheeled, amosii = Wheeled(arena), AmosII(arena)
    report = {
        "arena": "random",
        "arena_seed": 0,
        "steps": n,
        "repeats": args.repeats,
        "steer": steer.tolist(),
        "control_hz": wheeled.control_hz,
        "wheeled": {"timestep_s": wheeled.model.opt.timestep, "physics_steps_per_control_step": wheeled.n_substeps},
        "amosii": {"timestep_s": amosii.model.opt.timestep, "physics_steps_per_control_step": amosii.n_substeps},
        "control_steps_per_s": rate,
        "ratio_wheeled_over_amosii": rate["wheeled_fixed"] / rate["amosii_fixed"],
        "ratio_wheeled_over_amosii_plastic": rate["wheeled_plastic"] / rate["amosii_plastic"],
        "ratio_target": TARGET_RATIO,
        "mujoco_version": mujoco.__version__,
        "python": platform.python_version(),
        "cpus": os.cpu_count(),
    }
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "bodies.json").write_text(json.dumps(report, indent=2) + "\n")
    for loop in ("fixed", "plastic"):
        w, a = rate[f"wheeled_{loop}"], rate[f"amosii_{loop}"]
        print(f"{loop:8s} wheeled {w:8.0f} control steps/s   amosii {a:7.0f} control steps/s   ratio {w / a:5.1f}")
    print(f"target ratio >= {TARGET_RATIO:.0f}; wrote {args.out / 'bodies.json'}")


if __name__ == "__main__":
    main()
