"""Fig. 8: escape from a narrow passage, the paper's first real-robot experiment, in simulation.

The robot (physics body ``amosii``) starts inside the ``narrow-passage`` arena (a funnel whose end is two
obstacles with a gap narrower than the robot), facing the gap. The paper's robot walked toward the gap,
turned right at the obstacle on its left, got stuck in front of the gap, kept turning right as the left
neuron's weights grew, and escaped at 0:50 min (its controller ran at 27 Hz); with the static network it stayed
stuck. Here each network (plastic from zero weights, and static) runs ``seeds`` seeds (default 10; 3 with
``quick``) for :data:`STEPS` control steps at the control rate ``control_hz`` (10 Hz by default, the authors'
simulator; 27 Hz is the real robot's: as many steps, the networks' time), each stopped once escaped; the runs go
through the resumable store in the output folder. The json's ``real_robot`` entry puts the paper's interval from
its photos (obstacle seen at 0:10, escaped at 0:50) beside the simulated ones (a fair comparison at 27 Hz only).

The figure: a strip of rendered snapshots of the example seed for each network (times written on them), the
top view of every seed's path per network with the escape count, and the example runs' steering and weights.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.arenas import make_arena
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, outcome
from neurowalk.experiments.study_runs import Kept
from neurowalk.experiments.suites.real_robot import (
    EXAMPLE,
    N_SNAPSHOTS,
    NETWORKS,
    PATH,
    arena_geometry,
    config,
    draw_paths,
    draw_strip,
    draw_traces,
    example_of,
    network_arrays,
    real_robot_claims,
    run_record,
    snapshot_frames,
    with_path,
    write_videos,
)
from neurowalk.experiments.suites.timing import interval_s, real_robot_entry
from neurowalk.plotting.style import letter, pyplot, styled

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "fig8"
ARENA = "narrow-passage"
STEPS = 5000  # control steps per run at every rate: the paper's 5000 time steps of its Fig. 5B (500 s at 10 Hz)
PAPER_SEEN_S = 10.0  # the real robot detected the obstacle on its left at 0:10 min (paper §3, Fig. 8)
PAPER_ESCAPE_S = 50.0  # and escaped at 0:50 min
RULE = (
    "escaped: the trunk centre reached the arena's exit region (0.3 m or more behind the passage's mouth, the "
    "robot turned around and walked out) within the run's control steps; otherwise not escaped. Escape time: the "
    "first control step in the exit region / control_hz"
)


def runs(s: Settings) -> Iterator[Plan]:
    """Each network's ``s.seeds`` seeds (10; quick: 3) from ``s.seed``, each with its path, the first one (the
    example) in full; :data:`STEPS` control steps each at most."""
    for net in NETWORKS:
        for k in range(s.n(10, 3)):
            yield Plan(net, config(ARENA, {}, net, s.seed + k, STEPS), (PATH, EXAMPLE) if k == 0 else (PATH,))


def measure(s: Settings, runs: Mapping[str, Sequence[Kept]]) -> Result:
    """Each network's escapes over its seeds, the example seed ``seed`` in full (see the module doc)."""
    first = runs[NETWORKS[0]][0].config
    control_hz, n, steps = first.control_hz, len(runs[NETWORKS[0]]), first.steps
    examples = {net: example_of(runs[net][0]) for net in NETWORKS}
    arena = make_arena(ARENA)
    counts, arrays = {}, {}
    for net in NETWORKS:
        paths = with_path(runs[net])
        counts[net] = _counts(paths, s.seed)
        arrays.update(network_arrays(net, paths, examples[net], arena, examples[net]["summary"]["exit_step"]))
    keys = ("seed", "escaped", "exit_step", "trapped", "direction_switches", "final_weights")
    summary = {
        **run_record(s, arena, arena_geometry(arena), seeds=n, steps=steps, rule=RULE),
        "counts": counts,
        "escaped": {net: f"{counts[net]['escaped']}/{n}" for net in NETWORKS},
        "example": {net: {k: examples[net]["summary"][k] for k in keys} for net in NETWORKS},
        "snapshots": N_SNAPSHOTS,
        "real_robot": _real_robot(counts, n, steps, control_hz),
    }
    return Result(NAME, summary, arrays)


def render(res: Result) -> dict[str, np.ndarray]:
    """Each network's snapshot strip (``NET/frames``), rendered from the example's recorded positions."""
    return snapshot_frames(res.arrays, NETWORKS, make_arena(ARENA))


def videos(s: Settings, runs: Mapping[str, Sequence[Kept]], folder: Path) -> list[str]:
    """Each network's example run as an mp4 in ``folder`` (``--video``); the paths written."""
    return write_videos(NAME, make_arena(ARENA), {net: example_of(runs[net][0]) for net in NETWORKS}, folder)


def _real_robot(counts: dict[str, Any], n: int, steps: int, control_hz: float) -> dict[str, Any]:
    """The paper's interval from obstacle seen to escaped beside the plastic network's ``n`` seeds'."""
    return real_robot_entry(
        {
            "obstacle seen to escaped": (
                PAPER_ESCAPE_S - PAPER_SEEN_S,
                "detected the obstacle on its left (0:10 min), successfully escaped from the passage (0:50 min)",
                [interval_s(r["seen_time_s"], r["exit_time_s"]) for r in counts["plastic"]["runs"]],
            )
        },
        control_hz,
        steps / control_hz,
        f"the plastic network's {n} seeds (the static network did not escape on the real robot)",
    )


def _counts(runs: list[dict[str, Any]], seed: int) -> dict[str, Any]:
    """A network's escapes over its seeds' stored runs (seeds ``seed``, ``seed + 1``, ...), and each run's outcome
    (escape time in s)."""
    return {
        "seeds": len(runs),
        "escaped": sum(bool(r["escaped"]) for r in runs),
        "runs": [
            {
                "seed": seed + k,
                "escaped": bool(r["escaped"]),
                "exit_time_s": None if r["exit_step"] is None else r["exit_step"] / r["control_hz"],
                "seen_time_s": None if r["seen_step"] is None else r["seen_step"] / r["control_hz"],
                "trapped": r["trapped"],
                "direction_switches": r["direction_switches"],
                "final_pose": r["final_pose"],
                "final_weights": r["final_weights"],
            }
            for k, r in enumerate(runs)
        ],
    }


@styled
def plot(res: Result) -> Figure:
    """A-B: snapshot strips (one row per network); C-D: top views of every seed's path, the example's coloured by
    time; E-F: the examples' steering and weights over time. One row per subfigure."""
    plt = pyplot()
    s, a = res.summary, res.arrays
    arena = make_arena(s["arena"], **s["arena_opts"])
    fig = plt.figure(figsize=(16, 16), layout="constrained")
    rows = fig.subfigures(4, 1, height_ratios=[1.15, 1.15, 2.6, 2.2])
    for row, net in enumerate(NETWORKS):
        ex = s["example"][net]
        how = f"escaped at {ex['exit_step'] / s['control_hz']:.0f} s" if ex["escaped"] else "did not escape"
        axes = list(rows[row].subplots(1, N_SNAPSHOTS))
        label = f"{net}, seed {ex['seed']}: {how}"
        draw_strip(axes, a[f"{net}/frames"], list(a[f"{net}/snapshot_t"]), label, "AB"[row])
    grid = rows[2].add_gridspec(1, 2)
    for col, net in enumerate(NETWORKS):
        c = s["counts"][net]
        ax = rows[2].add_subplot(grid[0, col])
        paths = [a[f"{net}/path/{k}"] for k in range(c["seeds"])]
        draw_paths(
            ax,
            arena,
            paths,
            [r["escaped"] for r in c["runs"]],
            a[f"{net}/example/pose"],
            f"{net}: escaped {c['escaped']}/{c['seeds']} seeds",
            t=a[f"{net}/example/t"],
        )
        letter(ax, "CD"[col])
    grid = rows[3].add_gridspec(1, 2)
    for col, net in enumerate(NETWORKS):
        e = {k: a[f"{net}/example/{k}"] for k in ("t", "outputs", "b", "q")}
        title = f"{net}, seed {s['example'][net]['seed']}"
        top = draw_traces(rows[3], grid[0, col], e["t"], e["outputs"], e["b"], e["q"], title)
        letter(top, "EF"[col])
    fig.suptitle(
        f"Narrow passage (paper Fig. 8), {s['steps'] / s['control_hz']:.0f} s per run at {s['control_hz']:g} Hz: "
        "escaped " + ", ".join(f"{net} {s['escaped'][net]}" for net in NETWORKS)
    )
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The plastic network escapes the narrow passage; the static one stays trapped; at the real robot's control
    rate also its times (:func:`~neurowalk.experiments.suites.real_robot.real_robot_claims`)."""
    p, st = s["counts"]["plastic"], s["counts"]["static"]
    return [
        outcome("plastic network escapes the narrow passage (Fig. 8)", "escaped", p["escaped"], p["seeds"]),
        outcome(
            "static network fails to escape (Fig. 8, Supplementary Video 1)",
            "stuck",
            st["seeds"] - st["escaped"],
            st["seeds"],
        ),
        *real_robot_claims(s),
    ]
