"""The networks on other robots: the dead-end suite and Table 2 on AMOSII and on a wheeled robot at two sizes.

The paper closes: "the network can be applied to other mobile robot systems for generating adaptive obstacle
avoidance". This figure tests it. The same sensory networks (plastic and static; variant ``paper``) drive

- ``amosii``: the hexapod in MuJoCo, through the locomotion network (the paper's robot);
- ``wheeled``: a differential-drive robot with AMOSII's footprint, speed and rangefinders, the steering pair on its
  wheels (no locomotion network);
- ``wheeled x0.5``: the same robot at half the size and speed (distances read in its own units, so its sensors
  reach 0.2 m), in the same arenas: a small robot in a world made for a larger one.

Each body runs the dead ends of Fig. 3/5 (simple deadlock, narrow passage, corner; ``seeds`` seeds each,
:data:`~neurowalk.experiments.suites.deadends.TRAP_STEPS` steps, twice as many for the half-size robot, which is half as
fast: escaped or not) and Table 2 (the first ``environments``
random environments of table seed ``seed``, 2000 s: 20,000 steps at 10 Hz, both of Table 2's rules (not stuck;
coverage), Wilson 95% intervals). ``control_hz`` sets every run's control rate; the durations stay in seconds
(a dead end 500 s, Table 2 2000 s). All runs go through a resumable result store in the output folder (the dead
ends with their sampled paths).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.patches import Patch
from matplotlib.ticker import PercentFormatter

from neurowalk.arenas import make_arena
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study_runs import Kept
from neurowalk.experiments.suites.deadends import TRAP_STEPS
from neurowalk.experiments.suites.random_envs import (
    COVERAGE_CELL_M,
    DURATION_S,
    HELD_UP_RULE,
    LATCH,
    RULE,
    check_rate,
    coverage_rule,
    coverage_threshold,
    environments,
    outcome,
    row_counts,
    spec,
)
from neurowalk.experiments.suites.random_envs_plot import rate_bars
from neurowalk.experiments.suites.real_robot import PATH
from neurowalk.experiments.suites.timing import steps_for
from neurowalk.plotting import draw_arena
from neurowalk.plotting.style import (
    FONT,
    BarCount,
    legend_outside,
    letter_panels,
    network_colour,
    network_line,
    place_bar_counts,
    pyplot,
    styled,
)
from neurowalk.sim.config import UNTIL, EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

BODIES: dict[str, tuple[str, dict[str, float]]] = {
    "amosii": ("amosii", {}),
    "wheeled": ("wheeled", {}),
    "wheeled x0.5": ("wheeled", {"scale": 0.5}),
}
NETWORKS = ("plastic", "static")  # the networks compared (the Braitenberg vehicle: the surrogate's Table 2, escape-map)
DEAD_ENDS = ("simple-deadlock", "narrow-passage", "corner")
#: A row's Table 2 numbers: its name here (after ``table2_``) -> the name in Table 2's own counts (``row_counts``).
TABLE2_KEYS = {
    "success": "success",
    "failure": "failure",
    "environments": "environments",
    "rate": "success_rate",
    "ci95": "success_rate_95ci",
    "success_coverage": "success_coverage",
    "failure_coverage": "failure_coverage",
    "coverage_rate": "success_coverage_rate",
    "coverage_ci95": "success_coverage_rate_95ci",
    "median_coverage": "median_coverage",
    "coverage_quartiles": "coverage_quartiles",
    "held_up_300s_success": "held_up_300s_success",
}


def _dead_end(
    arena: str, net: str, body: str, opts: dict[str, float], steps: int, seed: int, control_hz: float
) -> dict[str, Any]:
    out: dict[str, Any] = {
        "arena": arena,
        "controller": net,
        "body": body,
        "steps": steps,
        "seed": seed,
        "control_hz": float(control_hz),
        "until": "escaped",  # only the outcome counts: a run stops once escaped
    }
    return {**out, "body_opts": opts} if opts else out


def _slower(steps: int, opts: dict[str, float]) -> int:
    """Dead-end steps for a body at ``scale`` < 1: as many more as it is slower, so it can cover the same distance."""
    return round(steps / min(1.0, opts.get("scale", 1.0)))


def plan(s: Settings) -> dict[str, Any]:
    """What :func:`runs` runs: ``n`` seeds per dead end, ``envs``, ``dead_steps`` and ``t2_steps`` (at the default body
    size), the durations in seconds, and the specs ``dead`` ((body, network, dead end, seed) -> spec) and ``table``
    ((body, network, environment seed) -> spec), every one at the control rate of ``s`` (10 Hz by default).

    ValueError on a body of :data:`BODIES` that cannot run at that rate.
    """
    control_hz, seed, n = s.rate, s.seed, s.n(10, 2)
    for body, _ in BODIES.values():
        check_rate(body, control_hz)
    n_env = 3 if s.quick and s.seeds is None else 5 * n
    dead_s, t2_s = (60.0, 100.0) if s.quick else (TRAP_STEPS / 10.0, DURATION_S)  # TRAP_STEPS: 5000 steps at 10 Hz
    dead_steps, t2_steps = steps_for(dead_s, control_hz), steps_for(t2_s, control_hz)
    envs = environments(n_env, seed)
    dead = {
        (b, net, a, s): _dead_end(a, net, body, opts, _slower(dead_steps, opts), seed + s, control_hz)
        for b, (body, opts) in BODIES.items()
        for net in NETWORKS
        for a in DEAD_ENDS
        for s in range(n)
    }
    table = {
        (b, net, e["seed"]): {
            **spec(e, net, t2_steps, body, control_hz=control_hz),
            **({"body_opts": opts} if opts else {}),
        }
        for b, (body, opts) in BODIES.items()
        for net in NETWORKS
        for e in envs
    }
    return {
        "n": n,
        "envs": envs,
        "dead_steps": dead_steps,
        "t2_steps": t2_steps,
        "dead_end_s": dead_s,
        "table2_s": t2_s,
        "dead": dead,
        "table": table,
    }


def runs(s: Settings) -> Iterator[Plan]:
    """Dead ends ``("dead", body, network, dead end)`` (each with its path, :data:`PATH`) and Table 2's runs
    ``("table", body, network)`` on every body of :data:`BODIES`: ``seeds`` runs per dead end, default 10, and 5x as
    many Table 2 environments; with ``quick`` 2 seeds and 3 environments of 100 s, dead ends of 60 s (a smoke
    test). Every run at the control rate of ``s`` (10 Hz by default)."""
    p = plan(s)
    for (b, net, a, _), one in p["dead"].items():
        yield Plan(("dead", b, net, a), EpisodeConfig.from_spec(one), (PATH,))
    for (b, net, _), one in p["table"].items():
        yield Plan(("table", b, net), EpisodeConfig.from_spec(one), (LATCH,))  # as Table 2's own runs keep them


def measure(s: Settings, runs: Mapping[tuple, Sequence[Kept]]) -> Result:
    """Dead-end escapes and Table 2 outcomes per body and network (see the module doc); the paths of seed 0."""
    p = plan(s)
    threshold = coverage_threshold(p["table2_s"])
    rows, paths = [], {}
    for b in BODIES:
        for net in NETWORKS:
            escapes = {a: sum(bool(r.escaped) for r in runs["dead", b, net, a]) for a in DEAD_ENDS}
            c = row_counts([{net: outcome(r.summary.to_dict(), threshold)} for r in runs["table", b, net]], net)
            rows.append({"body": b, "network": net, "dead_ends": escapes, "dead_end_runs": p["n"],
                         **{f"table2_{k}": c[key] for k, key in TABLE2_KEYS.items()}})  # fmt: skip
            for a in DEAD_ENDS:
                paths[f"{b}|{net}|{a}"] = np.array(runs["dead", b, net, a][0].kept["path"]["path"])
    summary = {
        "bodies": {b: {"body": body, "body_opts": opts} for b, (body, opts) in BODIES.items()},
        "networks": list(NETWORKS),
        "variant": "paper",
        "control_hz": s.rate,
        "dead_end_steps": p["dead_steps"],
        "dead_end_s": p["dead_end_s"],
        "dead_end_steps_by_body": {b: _slower(p["dead_steps"], opts) for b, (_, opts) in BODIES.items()},
        "table2_steps": p["t2_steps"],
        "table2_s": p["table2_s"],
        "table2_seed": s.seed,
        "interval": "Wilson score interval, 95%",
        "rows": rows,
        "rule": "dead ends: escaped = left the trap's exit region; Table 2: " + RULE,
        "stop_rule": "dead ends: " + UNTIL["escaped"] + "; Table 2's runs run all their steps",
        "coverage_rule": "Table 2: " + coverage_rule(p["table2_s"]),
        "coverage_threshold": threshold,
        "coverage_cell_m": COVERAGE_CELL_M,
        "held_up_rule": HELD_UP_RULE,
    }
    return Result("bodies", summary, arrays=paths)


#: Colour of each dead end's bars.
DEAD_END_COLOURS = ("#66C2A5", "#FC8D62", "#8DA0CB")
#: Width of each network's path (pt): the first drawn widest, so that paths on top of each other stay visible.
PATH_WIDTHS = (4.0, 2.4, 1.2)


def _bar_counts(ax: Axes, x: np.ndarray, heights: list[float], texts: list[str]) -> None:
    """Write each bar's count just above it (a zero bar too, so that an empty bar reads as none escaped)."""
    for xi, h, t in zip(x, heights, texts, strict=True):
        ax.text(xi, h + 0.02, t, ha="center", va="bottom", fontsize=FONT["small"], rotation=90)


@styled
def plot(res: Result) -> Figure:
    """A-C: paths in the narrow passage per body (each network its colour and dash); D: dead-end escapes per body
    and network; E: Table 2 success with intervals. One row per subfigure."""
    plt = pyplot()
    s = res.summary
    bodies = list(s["bodies"])
    fig = plt.figure(figsize=(16, 15), layout="constrained")
    rows = fig.subfigures(3, 1, height_ratios=[1.25, 1, 1])
    top = list(np.atleast_1d(rows[0].subplots(1, len(bodies))))
    for ax, b in zip(top, bodies, strict=True):
        draw_arena(ax, make_arena("narrow-passage"))
        for k, net in enumerate(s["networks"]):
            p = res.arrays.get(f"{b}|{net}|narrow-passage")
            if p is not None and len(p):
                ax.plot(p[:, 0], p[:, 1], lw=PATH_WIDTHS[k % len(PATH_WIDTHS)], label=net, **network_line(net))
        ax.set_title(f"{b}: narrow passage, seed {s['table2_seed']}")
    legend_outside(top[-1])
    rows_ = s["rows"]
    labels = [f"{r['body']}\n{r['network']}" for r in rows_]
    x = np.arange(len(rows_))
    ax = rows[1].add_subplot(1, 1, 1)
    width = 0.8 / len(DEAD_ENDS)
    for k, a in enumerate(DEAD_ENDS):
        v = [r["dead_ends"][a] / r["dead_end_runs"] for r in rows_]
        dx = (k - (len(DEAD_ENDS) - 1) / 2) * width
        ax.bar(x + dx, v, width * 0.95, color=DEAD_END_COLOURS[k % len(DEAD_END_COLOURS)], label=a)
        _bar_counts(ax, x + dx, v, [f"{r['dead_ends'][a]}/{r['dead_end_runs']}" for r in rows_])
    ax.set_xticks(x, labels, fontsize=FONT["note"])
    ax.set(ylim=(0, 1.25), xlabel="body, network", ylabel=f"escaped (share of {rows_[0]['dead_end_runs']} seeds)")
    ax.yaxis.set_major_formatter(PercentFormatter(1.0))
    ax.set_yticks([0, 0.25, 0.5, 0.75, 1.0])
    legend_outside(ax)
    ax.set_title(f"dead ends, {s['dead_end_steps']} control steps (the half-size robot twice as many)")
    panels = [*top, ax]
    ax = rows[2].add_subplot(1, 1, 1)
    both = all("table2_coverage_rate" in r for r in rows_)  # a json of the code before the coverage rule
    width = 0.4 if both else 0.8
    rules = [("table2_success", "table2_rate", "table2_ci95", "not stuck", 0.85, None)]
    if both:
        rules.append(
            ("table2_success_coverage", "table2_coverage_rate", "table2_coverage_ci95", "coverage rule", 0.45, "//")
        )
    colours = [network_colour(r["network"]) for r in rows_]
    handles: list[Patch] = []
    counts: list[BarCount] = []
    for j, (ok_key, rate_key, ci_key, label, alpha, hatch) in enumerate(rules):
        dx = (j - (len(rules) - 1) / 2) * width
        rate, ci = np.array([r[rate_key] for r in rows_]), np.array([r[ci_key] for r in rows_])
        texts = [f"{r[ok_key]}/{r['table2_environments']}" for r in rows_]
        counts += rate_bars(ax, x + dx, rate, ci, texts, width, color=colours, alpha=alpha, hatch=hatch)
        handles.append(Patch(fc="0.5", ec="k", lw=0.5, alpha=alpha, hatch=hatch, label=label))
    ax.set_xticks(x, labels, fontsize=FONT["note"])
    ax.set(ylim=(0, 1.05), xlabel="body, network", ylabel="success (Wilson 95% interval)")
    ax.yaxis.set_major_formatter(PercentFormatter(1.0))
    legend_outside(ax, handles=handles)
    title = f"Table 2, {rows_[0]['table2_environments']} environments, {s['table2_steps']} control steps"
    title += f" at {s.get('control_hz', 10.0):g} Hz"
    if "coverage_threshold" in s:
        title += f"; coverage rule: >= {s['coverage_threshold']:.2%} of the free {s['coverage_cell_m']:g} m cells"
    ax.set_title(title)
    letter_panels([*panels, ax])
    fig.suptitle(f"The same networks on other robots ({s.get('variant', 'paper')} variant)")
    place_bar_counts(fig, counts)  # once the layout is done: no count covers another bar or its error bar
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Beyond the paper: on every body the plastic network escapes at least as many dead ends as the static one and
    succeeds at least as often in random environments."""
    rows = {(r["body"], r["network"]): r for r in s["rows"]}
    claims = []
    for body in s["bodies"]:
        p, st = rows[(body, "plastic")], rows[(body, "static")]
        (pk, n), (sk, _) = ((sum(r["dead_ends"].values()), r["dead_end_runs"] * len(r["dead_ends"])) for r in (p, st))
        claims.append(
            holds(
                f"{body}: the plastic network escapes at least as many dead ends as the static one",
                "beyond the paper",
                pk >= sk,
                f"plastic {pk}/{n}, static {sk}/{n}",
                f"escaped runs over the dead ends {', '.join(p['dead_ends'])}, {p['dead_end_runs']} seeds each",
                unit="runs escaped",
            )
        )
        claims.append(
            holds(
                f"{body}: the plastic network is not stuck in at least as many random environments as the static one",
                "beyond the paper",
                p["table2_success"] >= st["table2_success"],
                f"plastic {p['table2_success']}/{p['table2_environments']}, static "
                f"{st['table2_success']}/{st['table2_environments']}",
                "Table 2 successes (not stuck at the end) of each network on the body",
                unit="environments not stuck",
            )
        )
    return claims
