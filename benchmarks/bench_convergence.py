"""Does a physics converge? Its headline measures against the same runs at a quarter of its step (issue 51).

For each physics of :data:`PHYSICS` (AMOSII's body options, each given in full) and its reference, the same
options at a quarter of its physics step (the same model otherwise), the same runs:

* **walks**: constant steering on the open floor (controller ``fixed``, seed 3): the nine sign pairs of Table 1 for
  600 control steps (60 s), their speed (cm/s) and turn rate (deg/s) after the 30 s warm-up and their direction
  by Table 1's rule; and the issue's three numbers: the yaw after 5 s walking straight (rad), the forward distance
  in 60 s walking straight (m) and the heading change in 60 s turning left (rad);
* **Fig. 7**: the gait's claims, judged by the figure's own rules;
* **climbing**: ``neurowalk run --arena steps --arena-opt height=H --climb --steps 3000 --seed S`` for H in
  0.06 ... 0.10 m and S in 0 ... 9 (stopped once climbed), and a 0.18 m wall (three seeds): climbs;
* **dead ends**: the simple dead end and the narrow passage, static and plastic network, ``--seeds`` seeds of 5000
  control steps (stopped once escaped): escapes, with 95% Wilson intervals;
* **Table 2 subset**: ``--environments`` random environments of the physics Table 2 (2000 s), the plastic network
  as the paper's equations read (``paper``) and as the authors' code has it (``original``): runs not stuck at the
  end by the table's rule, with 95% intervals;
* **cost**: the closed loop's control steps per second (box arena, plastic network, 3000 steps, the median of
  ``--repeats``, the physics interleaved), reference runs left out; ``before`` with the control step as it was
  then (:data:`SENSORS_EVERY_STEP`: sensors computed in every physics step, not the last one only).

A physics converges (``converged``) where: the yaw after 5 s is within 0.05 rad of the reference's; the 60 s
distance and heading change within 5%; the nine directions the same; Fig. 7's claims the same; and every count
agrees with the reference's (the share of either inside the other's 95% Wilson interval: :func:`compatible`). Runs
two at a time (a process pool of ``--workers``); ``--rejudge FILE`` judges a written result again by these rules
(its runs are not run again).

Run: ``python benchmarks/bench_convergence.py [--seeds 20] [--environments 20] [--out FILE]`` (default
``docs/benchmarks/convergence.json``); ``--only NAME`` measures one physics of :data:`PHYSICS`, ``--light NAME`` only
its walks and Fig. 7.
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import time
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from neurowalk.body.amosii import AmosII
from neurowalk.body.amosii_params import BodyParams
from neurowalk.body.registry import body_settings
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import fig7, table1
from neurowalk.experiments.study import compute
from neurowalk.experiments.study_runs import Term, run_all
from neurowalk.experiments.suites import random_envs
from neurowalk.experiments.suites.deadends import TRAP_STEPS
from neurowalk.experiments.suites.random_envs import wilson
from neurowalk.fileio import write_json
from neurowalk.sim.episode import Episode, EpisodeConfig, run_episode

#: What the two physics below share: the step, the solver, the cone, the servos' rotors, the contacts.
SHARED = {
    "timestep": 0.01,
    "solver": "Newton",
    "cone": "elliptic",
    "solver_iterations": 20,
    "solver_tolerance": 1e-6,
    "armature": 0.005,
    "contact_timeconst": 0.02,
}
PHYSICS: dict[str, dict[str, Any]] = {
    # The physics before issue 51: implicitfast, servos without a lag (MuJoCo's dense Jacobian for AMOSII).
    "before": {**SHARED, "integrator": "implicitfast", "servo_timeconst": 0.0, "jacobian": "auto"},
    # The adopted physics: the discrete integrator (the servos' stiffness and damping implicit) and servos that
    # follow their targets with a 30 ms lag.
    "adopted": {**SHARED, "integrator": "discrete", "servo_timeconst": 0.03, "jacobian": "sparse"},
}
#: The physics measured with the control step as it was before issue 51 (every physics step computes the sensors).
SENSORS_EVERY_STEP = ("before",)
QUARTER = 4  # the reference's physics step is the candidate's over this
WALK_STEPS = 600  # 60 s at 10 Hz (Table 1's runs)
WALK_SEED = 3
HEIGHTS = (0.06, 0.07, 0.08, 0.09, 0.10)  # m, the climbable steps
WALL = 0.18  # m, a step too high to climb
CLIMB_STEPS = 3000
CLIMB_SEEDS = 10  # the climbing runs' seeds 0 ... 9 (the issue's)
DEAD_ENDS = ("simple-deadlock", "narrow-passage")
NETWORKS = ("static", "plastic")
VARIANTS = ("paper", "original")
YAW_TOL = 0.05  # rad
REL_TOL = 0.05


def keep_walk(ep: Episode) -> dict[str, Any]:
    """A walk's numbers: Table 1's speed, turn rate and direction after the warm-up, and the issue's three."""
    pose = ep.trajectory.pose
    speed, turn = table1.pace(pose[table1.WARMUP :], ep.config.control_hz)
    heading = np.unwrap(pose[:, 2])
    return {
        "speed_cm_per_s": 100 * speed,
        "turn_rate_deg_per_s": turn,
        "direction": table1.direction(speed, turn),
        "yaw_5s_rad": float(pose[49, 2]),
        "forward_m": float(pose[-1, 0] - pose[0, 0]),
        "heading_change_rad": float(heading[-1] - heading[0]),
    }


def keep_outcome(ep: Episode) -> dict[str, Any]:
    """A run's outcome: escaped (or climbed), its exit step, and Table 2's row."""
    s = ep.summary
    row = {}
    if ep.config.arena == "random":
        row = random_envs.outcome(s, random_envs.coverage_threshold(random_envs.DURATION_S))
    return {"escaped": bool(s["escaped"]), "exit_step": s["exit_step"], "success": bool(row.get("success", False))}


#: What the benchmark keeps of a walk and of an outcome run (terms of the one runner).
WALK = Term("convergence walk", keep_walk)
OUTCOME = Term("convergence outcome", keep_outcome)


def configs(opts: dict[str, Any], seeds: int, environments: int) -> dict[str, list[EpisodeConfig]]:
    """Every run of one physics (its body options ``opts``), by measure."""
    walks = [
        EpisodeConfig(controller="fixed", steer=(float(a), float(b)), steps=WALK_STEPS, seed=WALK_SEED, body_opts=opts)
        for a, b in table1.SIGNS
    ]
    climbs = [
        EpisodeConfig(
            arena="steps",
            arena_opts={"height": h},
            controller="plastic",
            steps=CLIMB_STEPS,
            seed=s,
            reflexes=True,
            backbone=True,
            body_opts=opts,
            until="escaped",
        )
        for h in (*HEIGHTS, WALL)
        for s in range(CLIMB_SEEDS if h != WALL else 3)
    ]
    dead = [
        EpisodeConfig(arena=a, controller=n, steps=TRAP_STEPS, seed=s, body_opts=opts, until="escaped")
        for a in DEAD_ENDS
        for n in NETWORKS
        for s in range(seeds)
    ]
    envs = random_envs.environments(environments, 0)
    table2 = [
        EpisodeConfig.from_spec(
            {**random_envs.spec(e, "plastic", random_envs.STEPS, "amosii", variant=v), "body_opts": opts}
        )
        for v in VARIANTS
        for e in envs
    ]
    return {"walks": walks, "climbs": climbs, "dead_ends": dead, "table2": table2}


def counted(cfgs: list[EpisodeConfig], rows: list[dict[str, Any]], label: Any, rule: str) -> dict[str, Any]:
    """Counts of ``rule`` per group (``label(cfg)``), each with its 95% interval."""
    out: dict[str, Any] = {}
    for cfg, row in zip(cfgs, rows, strict=True):
        c = out.setdefault(label(cfg), {"runs": 0, rule: 0})
        c["runs"] += 1
        c[rule] += int(row[rule])
    for c in out.values():
        c["95ci"] = list(wilson(c[rule], c["runs"]))
    return out


def measure(opts: dict[str, Any], seeds: int, environments: int, workers: int, light: bool) -> dict[str, Any]:
    """Every measure of one physics (``light``: the walks and Fig. 7 only)."""
    t0 = time.perf_counter()
    runs = configs(opts, seeds, environments)
    walks = [r.kept[WALK.name] for r in run_all(runs["walks"], (WALK,), workers=workers, desc="walks")]
    out: dict[str, Any] = {"body_settings": body_settings("amosii", opts)}
    out["walks"] = {f"{int(c.steer[0]):+d},{int(c.steer[1]):+d}": w for c, w in zip(runs["walks"], walks, strict=True)}
    straight, left = out["walks"]["-1,-1"], out["walks"]["-1,+1"]
    out["yaw_5s_rad"], out["forward_60s_m"] = straight["yaw_5s_rad"], straight["forward_m"]
    out["heading_change_60s_rad"] = left["heading_change_rad"]
    _use(opts)
    claims = fig7.claims(compute(FIGURES["fig7"], Settings(quick=False)).summary, False)
    _use({})
    out["fig7_claims_reproduced"] = f"{sum(c.verdict == 'reproduced' for c in claims)}/{len(claims)}"
    for name, label, rule in (
        ()
        if light
        else (
            ("climbs", lambda c: f"{c.arena_opts['height']:.2f} m", "escaped"),
            ("dead_ends", lambda c: f"{c.arena} {c.controller}", "escaped"),
            ("table2", lambda c: f"plastic {c.variant}", "success"),
        )
    ):
        rows = [r.kept[OUTCOME.name] for r in run_all(runs[name], (OUTCOME,), workers=workers, desc=name)]
        out[name] = counted(runs[name], rows, label, rule)
    out["wall_time_s"] = time.perf_counter() - t0
    return out


_DEFAULTS = dict(BodyParams.__init__.__kwdefaults__)


def _use(opts: dict[str, Any]) -> None:
    """Make ``opts`` AMOSII's defaults in this process (for a figure that builds its own configs: Fig. 7)."""
    BodyParams.__init__.__kwdefaults__.update({**_DEFAULTS, **opts})


def closed_loops(steps: int, repeats: int) -> dict[str, float]:
    """Median control steps per second of the closed loop (box arena, plastic network) of each physics, the physics
    interleaved repeat by repeat (so that other load on the machine falls on all alike)."""
    run_episode(EpisodeConfig(arena="box", steps=5))
    rates: dict[str, list[float]] = {name: [] for name in PHYSICS}
    advance = AmosII.advance
    for _ in range(repeats):
        for name, opts in PHYSICS.items():
            cfg = EpisodeConfig(arena="box", controller="plastic", steps=steps, seed=0, body_opts=opts)
            if name in SENSORS_EVERY_STEP:
                AmosII.advance = _advance_before  # type: ignore[method-assign]
            try:
                t = time.perf_counter()
                run_episode(cfg)
                rates[name].append(steps / (time.perf_counter() - t))
            finally:
                AmosII.advance = advance  # type: ignore[method-assign]
    return {name: statistics.median(r) for name, r in rates.items()}


def _advance_before(self: AmosII) -> None:
    """A control step as before issue 51: ``n_substeps`` plain physics steps, each computing the sensors."""
    mujoco.mj_step(self.model, self.data, nstep=self.n_substeps)


def verdict(cand: dict[str, Any], ref: dict[str, Any]) -> dict[str, Any]:
    """The convergence checks of a physics against its reference: each check's numbers and whether it holds."""
    checks: dict[str, Any] = {
        "yaw_5s": {"diff_rad": cand["yaw_5s_rad"] - ref["yaw_5s_rad"], "tolerance_rad": YAW_TOL},
        "forward_60s": {"ratio": cand["forward_60s_m"] / ref["forward_60s_m"], "tolerance": REL_TOL},
        "heading_change_60s": {
            "ratio": cand["heading_change_60s_rad"] / ref["heading_change_60s_rad"],
            "tolerance": REL_TOL,
        },
    }
    checks["yaw_5s"]["holds"] = abs(checks["yaw_5s"]["diff_rad"]) <= YAW_TOL
    for k in ("forward_60s", "heading_change_60s"):
        checks[k]["holds"] = abs(checks[k]["ratio"] - 1) <= REL_TOL
    same = [k for k, w in cand["walks"].items() if w["direction"] == ref["walks"][k]["direction"]]
    checks["directions"] = {"same": len(same), "of": len(cand["walks"]), "holds": len(same) == len(cand["walks"])}
    checks["fig7"] = {"holds": cand["fig7_claims_reproduced"] == ref["fig7_claims_reproduced"]}
    for name, rule in (("climbs", "escaped"), ("dead_ends", "escaped"), ("table2", "success")):
        for group, c in cand.get(name, {}).items():
            r = ref[name][group]
            checks[f"{name}: {group}"] = {"count": c[rule], "reference": r[rule], "holds": compatible(c, r, rule)}
    return {"checks": checks, "converged": all(c["holds"] for c in checks.values())}


def compatible(a: dict[str, Any], b: dict[str, Any], rule: str) -> bool:
    """Two counts of ``rule`` agree: the share of either lies inside the other's 95% Wilson interval (so that 20 of
    20 and 19 of 20 agree, whichever is the reference: the interval of 19/20 ends at 0.99, that of 20/20 holds 0.95)."""

    def inside(x: dict[str, Any], y: dict[str, Any]) -> bool:
        lo, hi = y["95ci"]
        return lo <= x[rule] / x["runs"] <= hi

    return inside(a, b) or inside(b, a)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--environments", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--only", choices=tuple(PHYSICS), action="append", help="measure these physics only")
    ap.add_argument("--light", choices=tuple(PHYSICS), action="append", help="these physics: walks and Fig. 7 only")
    ap.add_argument("--out", type=Path, default=Path("docs/benchmarks/convergence.json"))
    ap.add_argument("--rejudge", type=Path, help="judge this written result again (no run) and write it to --out")
    args = ap.parse_args()
    if args.rejudge is not None:
        done = json.loads(args.rejudge.read_text())
        for p in done["physics"].values():
            p.update(verdict(p["measured"], p["reference"]))
        write_json(args.out, done)
        return
    loops = closed_loops(3000, args.repeats)
    physics: dict[str, Any] = {}
    for name in args.only or PHYSICS:
        opts = PHYSICS[name]
        step = body_settings("amosii", opts)["timestep"]
        fine = {**opts, "timestep": step / QUARTER}
        light = name in (args.light or ())
        cand = measure(opts, args.seeds, args.environments, args.workers, light)
        ref = measure(fine, args.seeds, args.environments, args.workers, light)
        physics[name] = {"body_opts": opts, "light": light, "control_steps_per_s": loops[name], "measured": cand,
                         "reference": ref, **verdict(cand, ref)}  # fmt: skip
        print(name, json.dumps(physics[name]["converged"]), flush=True)
    first = next(iter(PHYSICS))
    write_json(
        args.out,
        {
            "machine": f"{platform.system()} {platform.machine()}, {platform.processor() or 'cpu'}",
            "seeds": args.seeds,
            "environments": args.environments,
            "reference_step_over": QUARTER,
            "control_steps_per_s": loops,
            "speed_over_before": {name: loops[name] / loops[first] for name in PHYSICS},
            "physics": physics,
        },
    )


if __name__ == "__main__":
    main()
