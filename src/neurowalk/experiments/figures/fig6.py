"""Fig. 6: the plastic network in sixteen random environments (the first 16 of Table 2), each marked by its outcome.

As the paper's figure: red, failed (stuck at the end, Table 2's not-stuck rule); green, a success that faced a
confined space; blue, a success that faced a trap; by the rule of
:mod:`neurowalk.experiments.suites.confinement` (the arena's boxes and the trunk's path; its numbers are in the
json and on the picture). A success that faced neither is left unframed. Each environment also gets its coverage
and Table 2's coverage rule.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from neurowalk.body.registry import body_info
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds, rate
from neurowalk.experiments.study_runs import Kept, Term
from neurowalk.experiments.suites import confinement
from neurowalk.experiments.suites.random_envs import (
    COVERAGE_CELL_M,
    DURATION_S,
    QUICK_DURATION_S,
    RULE,
    SIZE,
    STUCK_S,
    arena_of,
    check_rate,
    coverage_rule,
    coverage_threshold,
    environments,
    spec,
)
from neurowalk.experiments.suites.timing import steps_for
from neurowalk.plotting import draw_arena
from neurowalk.plotting.style import FONT, OUTCOME_COLOURS, pyplot, styled, time_colorbar
from neurowalk.sim.config import EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from neurowalk.arenas.spec import ArenaSpec
    from neurowalk.sim.episode import Episode

#: Frame colour of each class (the paper's red, green and blue squares; a plain success unframed).
COLOURS = {
    "failed": OUTCOME_COLOURS["failed"],
    "passed a confined space": OUTCOME_COLOURS["ok"],
    "escaped a trap": OUTCOME_COLOURS["trap"],
    "plain success": None,
}


def pose_stride(control_hz: float) -> int:
    """Control steps between the kept poses: one a second of simulated time (10 at 10 Hz)."""
    return max(1, round(control_hz))


def keep_pose(ep: Episode) -> dict[str, Any]:
    """A run's pose (n, 3: x m, y m, yaw rad) every second of simulated time (:func:`pose_stride`)."""
    return {"pose": ep.trajectory.pose[:: pose_stride(ep.config.control_hz)]}


POSE = Term("pose", keep_pose, arrays={"pose": "float64"})

TRAP_ARENA = "simple-deadlock"  # the paper's own trap: the U-shaped dead end of Fig. 3A and 5A
TRAP_SEEDS = 5  # runs of the plastic network in it, on the figure's body
TRAP_STEPS_S = 500.0  # s of simulated time of each (Fig. 3A / 5A's 5000 time steps)
HISTOGRAM_ENVS, QUICK_HISTOGRAM_ENVS = 1000, 100  # Table 2 environments over which the measure is counted
BIN_DEG = 10.0  # the histogram's bins


def keep_blocked(ep: Episode) -> dict[str, Any]:
    """The widest angle (degrees) of directions meeting a box within the trap's reach along the run's path (its pose
    every second): :mod:`.confinement`'s measure, without keeping the path."""
    pose = ep.trajectory.pose[:: pose_stride(ep.config.control_hz)]
    return {"max_blocked_deg": float(confinement.situations(ep.arena, pose)["blocked_deg"].max())}


BLOCKED = Term("blocked", keep_blocked)


def _env_specs(s: Settings, n: int) -> list[dict[str, Any]]:
    """The run specs of the figure's network on its body in Table 2's first ``n`` environments."""
    body, hz = s.body or "surrogate", s.rate
    steps = steps_for(QUICK_DURATION_S if s.quick else DURATION_S, hz)
    return [spec(e, "plastic", steps, body, variant=s.variant or "paper", size=s.size or SIZE, params=s.params,
                 control_hz=hz) for e in environments(n, s.seed)]  # fmt: skip


def specs(s: Settings) -> list[dict[str, Any]]:
    """The sixteen run specs (ValueError where the body cannot run at the control rate: a surrogate runs at 10 Hz)."""
    check_rate(s.body or "surrogate", s.rate)
    return _env_specs(s, 16)


def runs(s: Settings) -> Iterator[Plan]:
    """The plastic network (Eq. 1-6 unless ``s.variant``) in the first 16 environments of Table 2 (same seeds), each
    with its pose every second; every run lasts the same simulated time (2000 s, quick 500 s) whatever the control
    rate."""
    for i, one in enumerate(specs(s)):
        yield Plan(i, EpisodeConfig.from_spec(one), (POSE,))
    for k, one in enumerate(trap_specs(s)):
        yield Plan(("trap", k), EpisodeConfig.from_spec(one), (POSE,))
    for i, one in enumerate(histogram_specs(s)):
        yield Plan(("histogram", i), EpisodeConfig.from_spec(one), (BLOCKED,))


def trap_specs(s: Settings) -> list[dict[str, Any]]:
    """The paper's own trap run by the figure's network and body: :data:`TRAP_SEEDS` runs in :data:`TRAP_ARENA`."""
    body, hz = s.body or "surrogate", s.rate
    steps = steps_for(TRAP_STEPS_S, hz)
    base = {"arena": TRAP_ARENA, "controller": "plastic", "body": body, "steps": steps, "control_hz": hz}
    extra = {"variant": s.variant} if s.variant and s.variant != "paper" else {}
    return [{**base, **extra, "seed": k, **({"params": s.params} if s.params else {})} for k in range(TRAP_SEEDS)]


def histogram_specs(s: Settings) -> list[dict[str, Any]]:
    """Table 2's first 1000 environments (quick: 100), the figure's network, for the measure's histogram: on a
    planar body only (none on a physics body: 1000 physics runs are a table of their own)."""
    if body_info(s.body or "surrogate").physics:
        return []
    return _env_specs(s, QUICK_HISTOGRAM_ENVS if s.quick else HISTOGRAM_ENVS)


def trap_threshold(paths: list[np.ndarray], arena: ArenaSpec) -> tuple[float, list[float]]:
    """The blocked angle (degrees) that makes a trap: the least, over the runs in the paper's own trap (their poses
    ``paths``, each (P, 3)), of the widest angle each met in it; and those widest angles."""
    widest = [float(confinement.situations(arena, p)["blocked_deg"].max()) for p in paths]
    return min(widest), widest


def measure(s: Settings, runs: Mapping[int, Sequence[Kept]]) -> Result:
    """Each environment's outcome, coverage and the confined spaces it met (:mod:`.confinement`)."""
    run_specs, envs, hz = specs(s), environments(16, s.seed), s.rate
    duration = QUICK_DURATION_S if s.quick else DURATION_S
    threshold = coverage_threshold(duration)
    stride = pose_stride(hz)
    arrays = {f"env{i}/pose": runs[i][0].kept["pose"]["pose"] for i in range(len(envs))}
    end_rows = round(STUCK_S * hz / stride)  # the kept poses of the last 300 s
    trap_arena = arena_of(trap_specs(s)[0])
    trap_deg, widest = trap_threshold([runs[("trap", k)][0].kept["pose"]["pose"] for k in range(TRAP_SEEDS)],
                                      trap_arena)  # fmt: skip
    blocked = np.array([runs[("histogram", i)][0].kept["blocked"]["max_blocked_deg"]
                        for i in range(len(histogram_specs(s)))])  # fmt: skip
    edges = np.arange(0.0, 360.0 + BIN_DEG, BIN_DEG)
    counts, _ = np.histogram(blocked, bins=edges)
    rows = []
    for i, (e, one) in enumerate(zip(envs, run_specs, strict=True)):
        r = runs[i][0]
        success = not r.trapped
        faced = confinement.classify(arena_of(one), arrays[f"env{i}/pose"], success, end_rows=end_rows,
                                     trap_deg=trap_deg)  # fmt: skip
        rows.append(
            {
                **e,
                "success": success,
                "outcome": faced.pop("class"),
                "coverage": r.coverage,
                "success_coverage": r.coverage >= threshold,
                "final_pose": list(r.final_pose),
                **faced,
            }
        )
    classes = Counter(r["outcome"] for r in rows)
    summary = {
        "body": s.body or "surrogate",
        "steps": run_specs[0]["steps"],
        "control_hz": hz,
        "duration_s": duration,
        "seed": s.seed,
        "rule": RULE,
        "coverage_rule": coverage_rule(duration),
        "coverage_threshold": threshold,
        "coverage_cell_m": COVERAGE_CELL_M,
        "class_rule": confinement.CLASS_RULE.replace(f">= {confinement.TRAP_BLOCKED_DEG:g} deg", f">= {trap_deg:g} deg")
        + f" (the trap's angle: the least of the widest angles the network met in the paper's own trap, the "
        f"{TRAP_ARENA} dead end of Fig. 3A / 5A, over {TRAP_SEEDS} runs on the same body)",
        "class_numbers": {**confinement.RULE_NUMBERS, "trap_blocked_deg": trap_deg},
        "trap_reference": {
            "arena": TRAP_ARENA,
            "seeds": TRAP_SEEDS,
            "duration_s": TRAP_STEPS_S,
            "widest_blocked_deg": widest,
            "trap_blocked_deg": trap_deg,
        },
        "blocked_histogram": None
        if not len(blocked)
        else {
            "environments": len(blocked),
            "bin_deg": BIN_DEG,
            "edges_deg": edges.tolist(),
            "counts": counts.tolist(),
            "at_least_trap": int(np.sum(blocked >= trap_deg)),
            "median_deg": float(np.median(blocked)),
        },
        "classes": {c: classes.get(c, 0) for c in confinement.CLASSES},
        "environments": rows,
        "variant": s.variant or "paper",
        "params": s.params,
        "box_size_m": s.size or SIZE,
        "success": sum(r["success"] for r in rows),
        "success_coverage": sum(r["success_coverage"] for r in rows),
        "pose_stride": stride,
        "pose_stride_s": stride / hz,
    }
    return Result("fig6", summary, arrays)


@styled
def plot(res: Result) -> Figure:
    """4 x 4 panels: arena, path coloured by time (one colour bar, s), start (red) and end (green) dots; framed by
    outcome: failed red, a confined space passed green, a trap escaped blue (the point it left marked by a ring of
    that colour); a legend of the frames below. The rules behind the classes are in the json."""
    plt = pyplot()
    s = res.summary
    hz = s.get("control_hz", 10.0)
    every_s = s.get("pose_stride_s", pose_stride(hz) / hz)
    fig = plt.figure(figsize=(13, 15), layout="constrained")
    axes = fig.subplots(4, 4, sharex=True, sharey=True)
    path = None
    for i, (ax, env) in enumerate(zip(axes.flat, s["environments"], strict=False)):
        arena = arena_of(spec(env, "plastic", 1, "surrogate", size=s.get("box_size_m", SIZE)))
        pose = res.arrays[f"env{i}/pose"]
        path = draw_arena(ax, arena, pose, margin=0.2, t=np.arange(len(pose)) * every_s) or path
        if path is not None:
            path.set_clim(0.0, s.get("duration_s", len(pose) * every_s))
        cls = env.get("outcome", "plain success" if env["success"] else "failed")
        cov = f", coverage {env['coverage']:.1%}" if env.get("coverage") is not None else ""
        ax.set_title(f"seed {env['seed']}: {env['n_boxes']} boxes{cov}\n{cls}", fontsize=FONT["note"] + 1)
        for key, colour in (
            ("left_trap", COLOURS["escaped a trap"]),
            ("left_confined", COLOURS["passed a confined space"]),
        ):
            if env.get(key) is not None:
                ax.plot(*env[key], "o", mfc="none", mec=colour, mew=2, ms=12, zorder=6)
        colour = COLOURS.get(cls)
        if colour is not None:
            for side in ax.spines.values():
                side.set_edgecolor(colour)
                side.set_linewidth(3)
        ax.label_outer()
    if path is not None:
        time_colorbar(path, axes, shrink=0.5)
    counts = s.get("classes", {})
    handles = [
        Patch(
            fc="none", ec=COLOURS[c] or "k", lw=3 if COLOURS[c] else 1, label=f"{c} ({counts[c]})" if c in counts else c
        )
        for c in COLOURS
    ]
    handles += [
        Line2D([], [], ls="none", marker="o", mfc="none", mec="0.3", mew=2, ms=12, label="where it left the space"),
        Line2D([], [], ls="none", marker="o", color="red", ms=7, label="start"),
        Line2D([], [], ls="none", marker="o", color="limegreen", mec="k", ms=7, label="end"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncol=4, title="frame: the run's class")
    fig.suptitle(
        f"Fig. 6: plastic network ({s.get('variant', 'paper')}) in 16 random environments ({s['body']}, "
        f"{s['steps'] / hz:g} s at {hz:g} Hz)\n{s['success']}/16 not stuck at the end"
        + (
            f"; a trap: {s['class_numbers']['trap_blocked_deg']:g} deg blocked, as in the paper's own dead end"
            if "trap_reference" in s
            else ""
        )
        + (f", {s['success_coverage']}/16 by coverage" if "success_coverage" in s else "")
    )
    return fig


def _histogram_words(s: dict[str, Any]) -> str:
    """The measure over Table 2's environments, in words ("" for a summary without it)."""
    h = s.get("blocked_histogram")
    if not h:
        return ""
    return (
        f"; over Table 2's first {h['environments']} environments the widest angle met has median "
        f"{h['median_deg']:.0f} deg, and {h['at_least_trap']} reach the trap's"
    )


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Sixteen random environments: the paper's one failure in sixteen, and successes that faced a confined space
    (green) and a trap (blue)."""
    rows = s["environments"]
    ok = sum(bool(r["success"]) for r in rows)
    classes = s["classes"]
    return [
        rate(f"random environments explored ({s['body']}, {s['steps']} steps; Fig. 6)", 15, 16, ok, len(rows)),
        holds(
            "successes that faced a confined space and a trap both occur (Fig. 6, green and blue)",
            "green and blue squares",
            classes["passed a confined space"] > 0 and classes["escaped a trap"] > 0,
            classes,
            s["class_rule"] + _histogram_words(s),
            unit="environments",
        ),
    ]
