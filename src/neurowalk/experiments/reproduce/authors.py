"""The second reference of ``neurowalk reproduce``: runs of the authors' own simulator, measured by neurowalk's rules.

The data (``authors_simulator/``, package data beside this module; its ``README.md`` says where it comes from) are
trajectories of the simulated AMOSII in LPZRobots with the authors' controller, one row per control step at
:data:`CONTROL_HZ`: row k (from 0) is t = (k + 1) / 10 s. Every number here is measured from them with neurowalk's
own functions (:mod:`neurowalk.metrics`, :func:`neurowalk.neural.cpg.period`,
:func:`neurowalk.experiments.figures.table1.pace`), never copied from the data's README:

* :func:`flat_ground`: Table 1's speed along the start heading and turning rate of the forced-steering runs;
* :func:`cpg_period`: the CPG period of the forward run (control steps);
* :func:`dead_ends`: the dead ends (escaped, exit time, trapped) for both networks and each seed;
* :func:`long_runs`: the 10,000 s runs in the difficult arena (coverage, wedged periods, trapped at the end);
  :func:`coverage_curve`: their coverage over time.

The logged pose is the rear trunk box's; :func:`trunk_pose` moves it :data:`REAR_BOX_M` forward along the heading
to the trunk centre, the point neurowalk's metrics follow.
"""

from __future__ import annotations

import functools
import gzip
from pathlib import Path
from typing import Any

import numpy as np

from neurowalk import metrics
from neurowalk.arenas import make_arena
from neurowalk.experiments.figures.table1 import PAPER, direction, pace
from neurowalk.experiments.suites.long_runs import WEDGED_LONG_S, FirstVisits
from neurowalk.neural.cpg import period
from neurowalk.sim.summarize import STUCK_S

#: The data's folder (package data: pyproject.toml's ``[tool.setuptools.package-data]`` ships it).
DATA = Path(__file__).with_name("authors_simulator")
CONTROL_HZ = 10.0  # control steps per second in every file (the authors' controller, every 10 physics steps)
REAR_BOX_M = 0.06  # m from the logged rear trunk box to the trunk centre, along the heading
TABLE1_WINDOW_S = (20.0, 320.0)  # s: the rows of the flat-ground runs that Table 1's measures use
#: The forced steering (O1, O2) of each flat-ground run, named as in the paper's Table 1 (O1 drives the right legs).
FLAT_GROUND = {"forward": (-1, -1), "turn left": (-1, 1), "turn right": (1, -1), "backward": (1, 1), "stop": (0, 0)}
FLAT_FILES = {"forward": "forward", "turn left": "left", "turn right": "right", "backward": "backward", "stop": "stop"}
DEAD_END_ARENAS = ("simple-deadlock", "narrow-passage")
NETWORKS = ("static", "plastic")
SEEDS = (10, 11, 12)  # the sensor-noise seeds of every dead end and network
MORE_SEEDS = {("simple-deadlock", "static"): (13, 14, 15, 16, 17, 18, 19)}  # further seeds of one cell
LONG_S = {("simple-deadlock", "static"): (10, 12)}  # seeds also run to 1,500 s (files ``*_1500s``)
US_RANGE_M = 0.4  # the readings are max(0, 1 - d / 0.4 m): 0 far, 1 near


def load(name: str) -> dict[str, np.ndarray]:
    """The columns of the data file ``name`` (relative to :data:`DATA`, e.g. ``"flat_ground/forward.csv.gz"``), by
    name, each (T,) float64, and ``t`` (s) from the row number."""
    with gzip.open(DATA / name, "rt", encoding="utf-8") as f:
        header = f.readline().strip().split(",")
        rows = np.loadtxt(f, delimiter=",", ndmin=2)
    if rows.shape[1] != len(header):
        raise ValueError(f"{name}: {rows.shape[1]} columns under a header of {len(header)}")
    cols = {c: rows[:, i] for i, c in enumerate(header)}
    cols["t"] = np.arange(1, len(rows) + 1) / CONTROL_HZ
    return cols


def trunk_pose(cols: dict[str, np.ndarray]) -> np.ndarray:
    """(T, 3) trunk-centre pose (x m, y m, yaw rad) from a file's rear-box ``x``, ``y``, ``yaw``."""
    yaw = cols["yaw"]
    return np.column_stack([cols["x"] + REAR_BOX_M * np.cos(yaw), cols["y"] + REAR_BOX_M * np.sin(yaw), yaw])


def us_distance(cols: dict[str, np.ndarray]) -> np.ndarray:
    """(T, 2) ultrasonic distances (m; :data:`US_RANGE_M` and beyond read as the range) from the readings."""
    return US_RANGE_M * (1.0 - np.column_stack([cols["us_L"], cols["us_R"]]))


@functools.cache
def flat_ground() -> dict[str, dict[str, Any]]:
    """Per Table 1 case: its steering ``O1``, ``O2``, ``speed_m_per_s`` along the start heading and
    ``turn_rate_deg_per_s`` (positive left) over :data:`TABLE1_WINDOW_S`, and ``direction`` as Table 1 names it."""
    lo, hi = (round(s * CONTROL_HZ) - 1 for s in TABLE1_WINDOW_S)  # rows of t = 20 s and t = 320 s
    out = {}
    for case, (o1, o2) in FLAT_GROUND.items():
        pose = trunk_pose(load(f"flat_ground/{FLAT_FILES[case]}.csv.gz"))[lo : hi + 1]
        speed, turn = pace(pose, CONTROL_HZ)
        out[case] = {
            "O1": o1,
            "O2": o2,
            "paper": PAPER.get((o1, o2)),
            "speed_m_per_s": speed,
            "turn_rate_deg_per_s": turn,
            "direction": direction(speed, turn),
        }
    return out


@functools.cache
def cpg_period() -> float:
    """The CPG period (control steps) of the forward run, from its ``cpg0`` output (:func:`neural.cpg.period`)."""
    cpg = load("flat_ground/forward.csv.gz")["cpg0"]
    return period(cpg - cpg.mean())


def dead_end_run(arena: str, network: str, seed: int, long: bool = False) -> dict[str, Any]:
    """One dead-end run by neurowalk's rules: ``escaped`` (the trunk centre reached the exit region), ``exit_s``
    (s: the exit row over the control rate, as neurowalk's ``RunSummary.exit_s``; None where never), ``trapped``
    (the last 300 s within a 0.5 m disc), ``end`` ([x, y] m, the last trunk centre) and ``end_heading_range_deg``
    (range of the heading over the last 300 s); ``long``: the 1,500 s file."""
    spec = make_arena(arena)
    pose = trunk_pose(load(f"dead_ends/{arena}_{network}_s{seed}{'_1500s' if long else ''}.csv.gz"))
    step = metrics.exit_step(pose, spec)
    tail = np.unwrap(pose[-round(STUCK_S * CONTROL_HZ) :, 2])
    return {
        "seed": seed,
        "seconds": len(pose) / CONTROL_HZ,
        "escaped": bool(metrics.escaped(pose, spec)),
        "exit_s": None if step is None else step / CONTROL_HZ,  # as RunSummary.exit_s
        "trapped": metrics.trapped(pose, window=round(STUCK_S * CONTROL_HZ)),
        "end": [round(float(v), 3) for v in pose[-1, :2]],
        "end_heading_range_deg": round(float(np.degrees(np.ptp(tail))), 1),
    }


@functools.cache
def dead_ends() -> dict[str, dict[str, dict[str, Any]]]:
    """Per dead end and network: ``runs``, ``escaped`` and ``trapped`` counts over :data:`SEEDS` (the 500 s runs),
    ``exit_s`` (sorted exit times, s), ``more`` (the same over :data:`MORE_SEEDS` too, where run) and ``long`` (the
    1,500 s runs of :data:`LONG_S`, where run); ``seeds``: every run of the cell."""
    out: dict[str, dict[str, dict[str, Any]]] = {}
    for arena in DEAD_END_ARENAS:
        for net in NETWORKS:
            extra = MORE_SEEDS.get((arena, net), ())
            runs = [dead_end_run(arena, net, s) for s in (*SEEDS, *extra)]
            cell = _counts(runs[: len(SEEDS)])
            if extra:
                cell["more"] = _counts(runs)
            if (arena, net) in LONG_S:
                cell["long"] = [dead_end_run(arena, net, s, long=True) for s in LONG_S[(arena, net)]]
            cell["seeds"] = runs
            out.setdefault(arena, {})[net] = cell
    return out


def _counts(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """``runs``, ``escaped``, ``trapped`` counts and the sorted ``exit_s`` of some :func:`dead_end_run` results."""
    exits = sorted(r["exit_s"] for r in runs if r["exit_s"] is not None)
    return {
        "runs": len(runs),
        "seed_list": [r["seed"] for r in runs],
        "escaped": sum(r["escaped"] for r in runs),
        "trapped": sum(r["trapped"] for r in runs),
        "exit_s": exits,
    }


@functools.cache
def long_runs() -> dict[str, dict[str, Any]]:
    """Per network, the 10,000 s run in the difficult arena: ``seconds``, ``coverage`` (share of the free 0.25 m
    cells), ``trapped`` at the end (last 300 s within 0.5 m), ``final`` ([x, y] m), the wedged periods' counts
    (:func:`metrics.wedged_summary`: ``wedged_periods``, ``longest_wedged_s``, ``wedged_causes``, the "both rays
    blind" cause from the ultrasonic readings; ``held_periods``, ``longest_held_s``, ``turning_periods``),
    ``over_300s`` and ``held_over_300s`` (wedged and held periods longer than 300 s) and ``wedged`` (each period's
    ``start_s``, ``duration_s``, ``heading_range_deg`` and ``held_s``)."""
    arena = make_arena("difficult")
    out = {}
    for net in NETWORKS:
        cols = load(f"difficult_arena/{net}.csv.gz")
        pose = trunk_pose(cols)
        wedged = metrics.wedged_periods(pose, control_hz=CONTROL_HZ, us_distance=us_distance(cols))
        held = metrics.held_periods(wedged, CONTROL_HZ)
        out[net] = {
            "seconds": len(pose) / CONTROL_HZ,
            "steps": len(pose),
            "coverage": metrics.coverage(pose, arena),
            "trapped": metrics.trapped(pose, window=round(STUCK_S * CONTROL_HZ)),
            "final": [round(float(v), 3) for v in pose[-1, :2]],
            **metrics.wedged_summary(wedged, CONTROL_HZ),
            "over_300s": sum(p["duration_s"] > WEDGED_LONG_S for p in wedged),
            "held_over_300s": sum(h["duration_s"] > WEDGED_LONG_S for h in held),
            "wedged": [
                {
                    "start_s": p["start"] / CONTROL_HZ,
                    "duration_s": p["duration_s"],
                    "heading_range_deg": p["heading_range_deg"],
                    "held_s": p["held_s"],
                }
                for p in wedged
            ],
        }
    return out


def coverage_curve(network: str, steps: np.ndarray) -> np.ndarray:
    """The share of the difficult arena's free 0.25 m cells that the authors' ``network`` had visited in its 10,000 s
    run by each control step of ``steps`` (:class:`~neurowalk.experiments.suites.long_runs.FirstVisits`, the cells of
    neurowalk's coverage; a step past the run's end reads its last)."""
    pose = trunk_pose(load(f"difficult_arena/{network}.csv.gz"))
    visits = FirstVisits(make_arena("difficult"))
    visits.add(pose, 0)
    return visits.curve(np.minimum(np.asarray(steps), len(pose) - 1))
