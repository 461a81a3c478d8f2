"""The 5 ms physics against the 10 ms one adopted by issue 39 (item 3): speed and behaviour side by side in one run.

Both with the integrator and servos of issue 39's time (:data:`ISSUE_39`); issue 51's physics is measured by
``bench_convergence.py``.

Two settings of the AMOSII model (``BodyParams``), both with the masses the authors' simulator applies (6.70 kg):

* ``5 ms``: the former physics step of 0.005 s (20 physics steps per 10 Hz control step), MuJoCo's default solver
  (100 iterations, tolerance 1e-8);
* ``adopted``: the defaults now: 0.01 s (the authors' step, 10 per control step), at most 20 iterations,
  tolerance 1e-6.

Each is measured on: the closed loop's control steps per second (``box`` arena, plastic network, the median of
``--repeats`` runs, the two settings interleaved); Table 1's speeds and turn rates (constant steering, 320 s, the
first 30 s left out); Fig. 7's gait (the figure's own judge); the dead ends over ``--seeds`` seeds (simple dead end
and narrow passage, static and plastic network, 5000 control steps, each run stopped once escaped), escape counts
with 95% Wilson intervals; and the physics Table 2 of the plastic network on ``--environments`` random environments
(2000 s each), its successes by both of the table's rules with 95% intervals. A setting is made the defaults of
``BodyParams`` in this process (and the workers it forks), so that every figure function runs with it.

Run: ``python benchmarks/bench_physics_settings.py [--seeds 20] [--environments 50] [--out FILE]`` (default
``docs/benchmarks/physics_settings.json``).
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import time
from pathlib import Path
from typing import Any

from neurowalk.body.amosii_params import BodyParams
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import fig7, table1
from neurowalk.experiments.study import compute
from neurowalk.experiments.study_runs import Kept, run_all, run_kept
from neurowalk.experiments.suites import random_envs
from neurowalk.experiments.suites.deadends import TRAP_STEPS
from neurowalk.experiments.suites.random_envs import wilson
from neurowalk.fileio import write_json
from neurowalk.sim.episode import EpisodeConfig, run_episode
from neurowalk.sim.run_summary import RunSummary

#: The physics of issue 39's time (implicitfast, servos without a lag), given to both: issue 51 adopted another.
ISSUE_39 = {"integrator": "implicitfast", "servo_timeconst": 0.0, "jacobian": "auto"}
SETTINGS: dict[str, dict[str, Any]] = {
    "5 ms": {**ISSUE_39, "timestep": 0.005, "solver_iterations": 100, "solver_tolerance": 1e-8},
    "adopted": dict(ISSUE_39),
}
STEERS = {"forward": (-1.0, -1.0), "turn left": (-1.0, 1.0), "turn right": (1.0, -1.0), "backward": (1.0, 1.0)}
TABLE1_STEPS = 3200  # 320 s at 10 Hz, the authors' simulator's window end
DEAD_ENDS = ("simple-deadlock", "narrow-passage")
NETWORKS = ("static", "plastic")


def use(setting: dict[str, Any]) -> None:
    """Make ``setting`` the defaults of ``BodyParams`` (this process and the workers it forks from now on)."""
    defaults = BodyParams.__init__.__kwdefaults__
    for name, value in {**_ADOPTED, **setting}.items():
        defaults[name] = value


_ADOPTED = {
    k: BodyParams.__init__.__kwdefaults__[k] for k in ("timestep", "solver_iterations", "solver_tolerance", *ISSUE_39)
}


def closed_loops(steps: int, repeats: int) -> dict[str, float]:
    """Median control steps per second of the closed loop (box arena, plastic network) under each setting, the
    settings interleaved repeat by repeat (so that other load on the machine falls on both alike)."""
    run_episode(EpisodeConfig(arena="box", steps=5))
    rates: dict[str, list[float]] = {name: [] for name in SETTINGS}
    for _ in range(repeats):
        for name, setting in SETTINGS.items():
            use(setting)
            t = time.perf_counter()
            run_episode(EpisodeConfig(arena="box", controller="plastic", steps=steps, seed=0))
            rates[name].append(steps / (time.perf_counter() - t))
    use({})
    return {name: statistics.median(r) for name, r in rates.items()}


def dead_ends(seeds: int) -> dict[str, Any]:
    """Escape counts per dead end and network over ``seeds`` seeds, with 95% intervals."""
    keys = [(a, n, s) for a in DEAD_ENDS for n in NETWORKS for s in range(seeds)]
    cfgs = [EpisodeConfig(arena=a, controller=n, steps=TRAP_STEPS, seed=s, until="escaped") for a, n, s in keys]
    out = [r.summary.to_dict() for r in run_all(cfgs, workers=2, progress=False)]
    counts: dict[str, Any] = {}
    for (a, n, _), r in zip(keys, out, strict=True):
        c = counts.setdefault(f"{a} {n}", {"runs": 0, "escaped": 0, "exit_s": []})
        c["runs"] += 1
        c["escaped"] += int(bool(r["escaped"]))
        if r["exit_step"] is not None:
            c["exit_s"].append(r["exit_step"] / r["control_hz"])
    for c in counts.values():
        exits = c.pop("exit_s")
        c["escaped_95ci"] = list(wilson(c["escaped"], c["runs"]))
        c["median_exit_s"] = statistics.median(exits) if exits else None
    return counts


def table2(environments: int) -> dict[str, Any]:
    """Table 2 on the physics AMOSII, the plastic network (paper variant), ``environments`` random environments of
    2000 s: successes by both of the table's rules, with 95% intervals."""
    envs = random_envs.environments(environments, 0)
    cfgs = [EpisodeConfig.from_spec(random_envs.spec(e, "plastic", random_envs.STEPS, "amosii")) for e in envs]
    threshold = random_envs.coverage_threshold(random_envs.DURATION_S)
    rows = [random_envs.outcome(k.summary.to_dict(), threshold) for k in run_all(cfgs)]
    out: dict[str, Any] = {"environments": environments}
    for rule in ("success", "success_coverage"):
        n = sum(bool(r[rule]) for r in rows)
        out[rule] = n
        out[f"{rule}_95ci"] = list(wilson(n, environments))
    return out


def measure(seeds: int, environments: int) -> dict[str, Any]:
    """Every measure of the current setting (no Table 2 where ``environments`` is 0)."""
    t0 = time.perf_counter()
    speeds = {}
    for name, steer in STEERS.items():
        r = run_kept((table1.WALK,), table1._walk(steer, TABLE1_STEPS, 0).spec())
        summary = RunSummary.from_dict({k: v for k, v in r.items() if k != "kept"})
        m, _ = table1._measured(Kept(summary, r["kept"]), 10.0)
        speeds[name] = {"speed_cm_per_s": 100 * m["speed_m_per_s"], "turn_rate_deg_per_s": m["turn_rate_deg_per_s"]}
    gait = compute(FIGURES["fig7"], Settings(quick=False)).summary
    claims = fig7.claims(gait, False)
    return {
        "table1": speeds,
        "fig7_claims_reproduced": f"{sum(c.verdict == 'reproduced' for c in claims)}/{len(claims)}",
        "dead_ends": dead_ends(seeds),
        **({"table2_plastic": table2(environments)} if environments else {}),
        "wall_time_s": time.perf_counter() - t0,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--environments", type=int, default=50, help="Table 2's environments (0: no Table 2)")
    ap.add_argument("--out", type=Path, default=Path("docs/benchmarks/physics_settings.json"))
    args = ap.parse_args()
    loops = closed_loops(3000, args.repeats)
    results = {}
    for name, setting in SETTINGS.items():
        use(setting)
        results[name] = {
            "body_params": {**_ADOPTED, **setting},
            "control_steps_per_s": loops[name],
            **measure(args.seeds, args.environments),
        }
        print(name, json.dumps(results[name]["table1"]), results[name]["control_steps_per_s"], flush=True)
    use({})
    base, new = results["5 ms"], results["adopted"]
    ratios = {
        "control_steps_per_s_adopted_over_5ms": new["control_steps_per_s"] / base["control_steps_per_s"],
        **{
            f"{k}_{q}_adopted_over_5ms": new["table1"][k][q] / base["table1"][k][q]
            for k in STEERS
            for q in ("speed_cm_per_s", "turn_rate_deg_per_s")
            if (k in ("forward", "backward")) == q.startswith("speed")
        },
    }
    write_json(
        args.out,
        {
            "machine": f"{platform.system()} {platform.machine()}, {platform.processor() or 'cpu'}",
            "total_mass_kg": BodyParams().total_mass,
            "seeds": args.seeds,
            "settings": results,
            "ratios": ratios,
        },
    )
    print(json.dumps(ratios, indent=1))


if __name__ == "__main__":
    main()
