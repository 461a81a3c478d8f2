"""Why climbing failed at the 10 ms physics step, and what climbed (issue 44): physics settings side by side.

The former physics (before issue 51: implicitfast, servos without a lag) is given in full to every setting below, so
that the script measures what it measured then; the adopted physics is measured by ``bench_convergence.py``.

The run is the user's ``neurowalk run --arena steps --arena-opt height=H --climb --steps 3000 --seed S`` (plastic
network, leg reflexes and backbone control, the step's edge 0.5 m ahead), for H in 0.06 ... 0.10 m and S in
0 ... ``--seeds`` - 1, each stopped once the trunk centre is 0.3 m onto the platform (climbed). Physics settings of
the AMOSII model, its solver as adopted (at most 20 iterations to 1e-6) unless said:

* ``10 ms``: the adopted walking step, 0.01 s, MuJoCo's ``implicitfast`` integrator;
* ``10 ms, 100 iterations``: the same with MuJoCo's default solver (at most 100 iterations to 1e-8);
* ``5 ms``: 0.005 s, ``implicitfast`` (what a climbing run used from issue 44 to issue 51);
* ``10 ms RK4``: 0.01 s with the 4th-order Runge-Kutta integrator (set on the built model).

For each: climbed counts per height; the robot's yaw after the start's first 50 control steps and where its trunk
centre first passes x = 0.25 m (the front face then 0.04 m from the step's edge), as the median and range over the
runs (rad; the robot starts facing the step, yaw 0); and the physics' microseconds per control step (the median of
the runs' physics time over their control steps). Runs two at a time (a process pool of ``--workers``).

Run: ``python benchmarks/bench_climbing_physics.py [--seeds 10] [--out FILE]`` (default
``docs/benchmarks/climbing_physics.json``).
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from neurowalk.body.amosii_mjcf import trunk_pose
from neurowalk.fileio import write_json
from neurowalk.metrics import exit_step
from neurowalk.sim.config import build, seeds
from neurowalk.sim.episode import EpisodeConfig

FORMER = {"servo_timeconst": 0.0, "jacobian": "auto"}  # with the integrator set below: the physics before issue 51
SETTINGS: dict[str, tuple[dict[str, Any], str]] = {
    "10 ms": ({**FORMER, "timestep": 0.01}, "implicitfast"),
    "10 ms, 100 iterations": (
        {**FORMER, "timestep": 0.01, "solver_iterations": 100, "solver_tolerance": 1e-8},
        "implicitfast",
    ),
    "5 ms": ({**FORMER, "timestep": 0.005}, "implicitfast"),
    "10 ms RK4": ({**FORMER, "timestep": 0.01}, "RK4"),
}
HEIGHTS = (0.06, 0.07, 0.08, 0.09, 0.10)  # m
STEPS = 3000  # control steps (300 s at 10 Hz)
APPROACH_X = 0.25  # m: the trunk centre's x where the approach yaw is read


def one(job: tuple[str, float, int]) -> dict[str, Any]:
    """One run of a setting at a height and seed: climbed, its step, the yaws, the physics' time per control step."""
    setting, height, seed = job
    body_opts, integrator = SETTINGS[setting]
    cfg = EpisodeConfig(arena="steps", arena_opts={"height": height}, controller="plastic", steps=STEPS, seed=seed,
                        reflexes=True, backbone=True, body_opts=body_opts)  # fmt: skip
    arena, body, ctrl = build(cfg)
    body.model.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator.upper()}")
    body_rng, ctrl_rng, _ = seeds(cfg)
    body.reset(body_rng)
    ctrl.reset(ctrl_rng)
    pose = np.zeros((STEPS, 3))
    physics = 0.0
    x0, x1, y0, y1 = arena.exit_region  # the CPU loop's stop rule (until="escaped")
    done = STEPS
    for k in range(STEPS):
        body.apply(ctrl.act(body.observe()))
        t = time.perf_counter()
        body.advance()
        physics += time.perf_counter() - t
        pose[k] = trunk_pose(body.model, body.data)  # no sensor read: its noise draws would change the run
        if x0 <= pose[k, 0] <= x1 and y0 <= pose[k, 1] <= y1:
            done = k + 1
            break
    pose = pose[:done]
    passed = np.flatnonzero(pose[:, 0] >= APPROACH_X)
    return {
        "setting": setting,
        "height_m": height,
        "seed": seed,
        "climbed_step": exit_step(pose, arena),
        "yaw_at_50_rad": float(pose[min(49, done - 1), 2]),
        "approach_yaw_rad": float(pose[passed[0], 2]) if len(passed) else None,
        "physics_us_per_control_step": physics / done * 1e6,
    }


def _spread(values: list[float]) -> dict[str, float]:
    return {"median": statistics.median(values), "min": min(values), "max": max(values)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=Path("docs/benchmarks/climbing_physics.json"))
    args = ap.parse_args()
    jobs = [(s, h, k) for s in SETTINGS for h in HEIGHTS for k in range(args.seeds)]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        runs = []
        for i, r in enumerate(pool.map(one, jobs), 1):
            runs.append(r)
            print(f"\r{i}/{len(jobs)} runs, {time.perf_counter() - t0:.0f} s", end="", flush=True)
    print()
    out: dict[str, Any] = {}
    for s, (body_opts, integrator) in SETTINGS.items():
        mine = [r for r in runs if r["setting"] == s]
        climbed = {f"{h:.2f}": sum(r["climbed_step"] is not None for r in mine if r["height_m"] == h) for h in HEIGHTS}
        approach = [r["approach_yaw_rad"] for r in mine if r["approach_yaw_rad"] is not None]
        out[s] = {
            "body_opts": body_opts,
            "integrator": integrator,
            "climbed": climbed,
            "climbed_all": sum(climbed.values()),
            "runs": len(mine),
            "yaw_at_50_rad": _spread([r["yaw_at_50_rad"] for r in mine]),
            "approach_yaw_rad": _spread(approach),
            "physics_us_per_control_step": statistics.median(r["physics_us_per_control_step"] for r in mine),
        }
        print(s, out[s]["climbed"], f"yaw(50) {out[s]['yaw_at_50_rad']['median']:+.2f}",
              f"approach {out[s]['approach_yaw_rad']['median']:+.2f}",
              f"{out[s]['physics_us_per_control_step']:.0f} us")  # fmt: skip
    base = out["10 ms"]["physics_us_per_control_step"]
    for s in SETTINGS:
        out[s]["physics_cost_x_10ms"] = out[s]["physics_us_per_control_step"] / base
    write_json(args.out, {
        "what": __doc__.splitlines()[0],
        "command": "neurowalk run --arena steps --arena-opt height=H --climb --steps 3000 --seed S (until climbed)",
        "heights_m": list(HEIGHTS), "seeds": args.seeds, "settings": out, "runs": runs,
        "machine": {"python": platform.python_version(), "machine": platform.machine(), "workers": args.workers},
        "mujoco": mujoco.__version__, "wall_time_s": time.perf_counter() - t0,
    })  # fmt: skip
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
