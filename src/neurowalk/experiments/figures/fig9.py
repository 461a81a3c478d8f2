"""Fig. 9: navigation in a complex path, the paper's second real-robot experiment, in simulation.

The ``complex-path`` arena (a wall on the right, small obstacles on the left, a dead end; its geometry and the
reasons for it are in :mod:`neurowalk.arenas.generated`). The paper's robot entered the path, turned right at
an obstacle on its left, walked to the end, turned left away from the dead end and went out of the path at
3:20 min (its controller ran at 27 Hz); with the static network it got stuck in the path. Each network (plastic
from zero weights, and static) runs ``seeds`` seeds (default 10; 3 with ``quick``) for :data:`STEPS` control
steps at the control rate ``control_hz`` (10 Hz by default, the authors' simulator; 27 Hz is the real robot's: as
many steps, the networks' time), each stopped once out on the left; then width and obstacle spacing are swept by
-20%, 0, +20% (a 3 x 3 map,
``seeds`` seeds per cell; no sweep with ``quick``, nor at a rate other than the simulator's: the map is a study of
the simulated robot, the other rates are there for the real-robot comparison, which runs the default geometry).
Every run goes through the resumable store in the output folder. The outcome rule is :func:`outcome` (written
into the json). The json's ``real_robot`` entry puts the paper's intervals between its photos (obstacle seen at
0:20, end of the path approached at 1:08, out of the path at 3:20) beside the simulated ones (a fair comparison at
27 Hz only).

The figure: a strip of rendered snapshots of the example seed for each network (times written on them), the
top view of every seed's path, the outcome map of each network, and the example runs' steering and weights.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurowalk.arenas import arena_options, make_arena
from neurowalk.arenas.deadlocks import EXIT_MARGIN, WALL
from neurowalk.arenas.generated import MOUTH, OPENING
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim
from neurowalk.experiments.reproduce.claims import outcome as outcome_claim
from neurowalk.experiments.study_runs import Kept
from neurowalk.experiments.suites.real_robot import (
    EXAMPLE,
    N_SNAPSHOTS,
    NETWORKS,
    PATH,
    PATH_EVERY_S,
    arena_geometry,
    config,
    draw_paths,
    draw_strip,
    draw_traces,
    example_of,
    network_arrays,
    path_every,
    real_robot_claims,
    run_record,
    snapshot_frames,
    with_path,
    write_videos,
)
from neurowalk.experiments.suites.timing import SIM_HZ, interval_s, real_robot_entry
from neurowalk.plotting.style import FONT, colorbar, letter, pyplot, styled

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from neurowalk.arenas.spec import ArenaSpec

NAME = "fig9"
ARENA = "complex-path"
# 8000 control steps at every rate (800 s at 10 Hz): three times the 2,590 steps the robot needs to walk the 3 m path
# straight on open floor (1.16 cm/s at 10 Hz), after the paper's timeline (the end reached at 1:08 min, out of the
# path at 3:20 min: 2.9 times as long); they hold the static robot's window (STUCK_WINDOW_STEPS) with room to see
# where its outcome flips.
STEPS = 8000
PAPER_SEEN_S = 20.0  # the real robot detected an obstacle on its left at 0:20 min (paper §3, Fig. 9)
PAPER_END_S = 68.0  # the real robot approached the end of the path at 1:08 min (paper §3, Fig. 9)
PAPER_OUT_S = 200.0  # and went out of the path at 3:20 min
FACTORS: tuple[float, ...] = (0.8, 1.0, 1.2)  # width and spacing sweep: -20%, 0, +20%
OUT_LEFT, OUT_END = "out (left side)", "out (open end)"
STUCK_END, STUCK_PATH = "stuck at the dead end", "stuck in the path"
OUTCOMES: tuple[str, ...] = (OUT_LEFT, OUT_END, STUCK_END, STUCK_PATH)
RULE = (
    f"out (left side): the trunk centre got more than {EXIT_MARGIN} m beyond the outer edge of the left obstacle "
    f"row (the arena's exit region); out (open end): more than {EXIT_MARGIN} m behind the start (the path's "
    f"open end is {MOUTH} m ahead of it) or more than {EXIT_MARGIN} m beyond the right wall's outer face (round "
    f"the wall's start); whichever came first, checked on the path sampled every {PATH_EVERY_S:g} s of simulated "
    "time. "
    f"Otherwise stuck (still in the path at the end of the run): at the dead end if the trunk centre got "
    f"alongside the opening before the end wall (within {OPENING} m of it), else in the path. "
    "Got out = either 'out' outcome. Reached the end: the first path point alongside the opening."
)


def outcome(xy: np.ndarray, arena: ArenaSpec) -> tuple[str, int | None]:
    """Outcome of a ``complex-path`` run from its trunk path ``xy`` (n, 2) m: (one of :data:`OUTCOMES`, row out).

    The row is the first row of ``xy`` outside the path (None when it never got out); see :data:`RULE`.
    """
    o = arena.options
    left = xy[:, 1] >= arena.exit_region[2]
    back = (xy[:, 0] <= arena.start[0] - EXIT_MARGIN) | (xy[:, 1] <= -o["width"] / 2 - WALL - EXIT_MARGIN)
    out = np.flatnonzero(left | back)
    if len(out):
        i = int(out[0])
        return (OUT_LEFT if left[i] else OUT_END), i
    reached = reached_end(xy, arena) is not None
    return (STUCK_END if reached else STUCK_PATH), None


def reached_end(xy: np.ndarray, arena: ArenaSpec) -> int | None:
    """First row of the trunk path ``xy`` (n, 2) m alongside the opening before the end wall (None: never)."""
    idx = np.flatnonzero(xy[:, 0] >= MOUTH + arena.options["length"] - OPENING)
    return int(idx[0]) if len(idx) else None


def _cell(width_f: float, spacing_f: float) -> dict[str, float]:
    d = arena_options(ARENA)
    return {"width": round(d["width"] * width_f, 6), "spacing": round(d["spacing"] * spacing_f, 6)}


def _cells(s: Settings) -> list[tuple[float, float]]:
    """The outcome map's (width, spacing) factors: :data:`FACTORS` squared, the default geometry only with
    ``quick`` or away from the simulator's rate."""
    factors = FACTORS if not s.quick and s.rate == SIM_HZ else (1.0,)
    return [(fw, fs) for fw in factors for fs in factors]


def runs(s: Settings) -> Iterator[Plan]:
    """Each network's ``s.seeds`` seeds (10; quick: 3) from ``s.seed`` in the default geometry, then in each cell of
    the outcome map (labelled ``(network, cell)``), each with its path, the first one (the example) in full;
    :data:`STEPS` control steps each at most."""
    for c in dict.fromkeys([(1.0, 1.0), *_cells(s)]):  # first the default geometry, then the map's other cells
        for net in NETWORKS:
            for k in range(s.n(10, 3)):
                first = k == 0 and c == (1.0, 1.0)
                terms = (PATH, EXAMPLE) if first else (PATH,)
                yield Plan((net, c), config(ARENA, _cell(*c), net, s.seed + k, STEPS), terms)


def measure(s: Settings, runs: Mapping[tuple, Sequence[Kept]]) -> Result:
    """Each network's outcomes over its seeds in each geometry, the example seed ``seed`` in full (see the module
    doc)."""
    first = runs[NETWORKS[0], (1.0, 1.0)][0].config
    control_hz, n, steps = first.control_hz, len(runs[NETWORKS[0], (1.0, 1.0)]), first.steps
    cells = _cells(s)
    factors = sorted({c[0] for c in cells})
    examples = {net: example_of(runs[net, (1.0, 1.0)][0]) for net in NETWORKS}

    def stored(net: str, cell: tuple[float, float] = (1.0, 1.0)) -> list[dict[str, Any]]:
        return with_path(runs[net, cell])

    arena = make_arena(ARENA)
    every = path_every(control_hz)
    counts, arrays = {}, {}
    for net in NETWORKS:
        counts[net], more = _network(net, stored(net), examples[net], s.seed, arena, every)
        arrays.update(more)
    summary = {
        **run_record(s, arena, _geometry(arena), seeds=n, steps=steps, rule=RULE, path_every_steps=every),
        "outcomes": list(OUTCOMES),
        "counts": counts,
        "sweep_factors": list(factors),
        "map": [_map_cell(c, {net: stored(net, c) for net in NETWORKS}) for c in cells],
        "example": {net: _example(examples[net], s.seed) for net in NETWORKS},
        "snapshots": N_SNAPSHOTS,
        "real_robot": _real_robot(counts, n, steps, control_hz),
    }
    return Result(NAME, summary, arrays)


def render(res: Result) -> dict[str, np.ndarray]:
    """Each network's snapshot strip (``NET/frames``, 480 x 270), rendered from the example's recorded positions."""
    return snapshot_frames(res.arrays, NETWORKS, make_arena(ARENA), width=480, height=270)


def videos(s: Settings, runs: Mapping[tuple, Sequence[Kept]], folder: Path) -> list[str]:
    """Each network's example run as an mp4 in ``folder`` (``--video``); the paths written."""
    examples = {net: example_of(runs[net, (1.0, 1.0)][0]) for net in NETWORKS}
    return write_videos(NAME, make_arena(ARENA), examples, folder)


def _network(
    net: str, runs: list[dict[str, Any]], example: dict[str, Any], seed: int, arena: ArenaSpec, every: int
) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """A network's counts over its seeds' ``runs`` in the default geometry (:func:`_tally` of :func:`_seed_rows`)
    and its arrays (:func:`network_arrays`); marks its ``example`` run with its outcome and the step it got out."""
    rows = _seed_rows(runs, seed, arena, every)
    example["outcome"], example["out_step"] = outcome(example["pose"][:, :2], arena)
    arrays = network_arrays(net, runs, example, arena, example["out_step"])
    return {**_tally([x["outcome"] for x in rows]), "runs": rows}, arrays


def _seed_rows(runs: list[dict[str, Any]], seed: int, arena: ArenaSpec, every: int) -> list[dict[str, Any]]:
    """Each seed's stored run in the default geometry (seeds ``seed``, ``seed + 1``, ...): its outcome, the times
    (s) it reached the end and got out (from its path, stored every ``every`` control steps), its final state."""

    def path_time_s(row: int | None, r: dict[str, Any]) -> float | None:
        """Time (s) of a row of a stored path (every ``every``-th control step, and the last: the step the run
        stopped at, out on the left, or its last)."""
        if row is None:
            return None
        last = r["exit_step"] if r["exit_step"] is not None else r["steps"] - 1
        return min(row * every, last) / r["control_hz"]

    rows = []
    for k, r in enumerate(runs):
        xy = np.asarray(r["path"])
        label, i = outcome(xy, arena)
        rows.append(
            {
                "seed": seed + k,
                "outcome": label,
                "got_out": label in (OUT_LEFT, OUT_END),
                "seen_time_s": None if r["seen_step"] is None else r["seen_step"] / r["control_hz"],
                "end_time_s": path_time_s(reached_end(xy, arena), r),
                "out_time_s": path_time_s(i, r),
                "final_pose": r["final_pose"],
                "final_weights": r["final_weights"],
                "direction_switches": r["direction_switches"],
            }
        )
    return rows


def _tally(labels: list[str]) -> dict[str, int]:
    """Counts of outcome ``labels`` (one per seed): seeds, got out, and each of :data:`OUTCOMES`."""
    return {
        "seeds": len(labels),
        "got_out": sum(lab in (OUT_LEFT, OUT_END) for lab in labels),
        **{lab: labels.count(lab) for lab in OUTCOMES},
    }


def _map_cell(cell: tuple[float, float], runs: dict[str, list[dict[str, Any]]]) -> dict[str, Any]:
    """One cell of the outcome map: the geometry (width and spacing factors) and each network's :func:`_tally` over
    its seeds' stored ``runs`` in it ({network: [run with its path, per seed]})."""
    fw, fs = cell
    arena = make_arena(ARENA, **_cell(fw, fs))
    entry: dict[str, Any] = {"width_factor": fw, "spacing_factor": fs, "arena_opts": arena.options}
    for net, seeds in runs.items():
        entry[net] = _tally([outcome(np.asarray(r["path"]), arena)[0] for r in seeds])
    return entry


def _example(ex: dict[str, Any], seed: int) -> dict[str, Any]:
    """The example run's record: seed, outcome, the time (s) it got out (None: never), final weights."""
    return {
        "seed": seed,
        "outcome": ex["outcome"],
        "out_time_s": None if ex["out_step"] is None else float(ex["t"][ex["out_step"]]),
        "final_weights": ex["summary"]["final_weights"],
    }


def _real_robot(counts: dict[str, Any], n: int, steps: int, control_hz: float) -> dict[str, Any]:
    """The paper's intervals (obstacle seen to the end approached, to out of the path) beside the plastic network's
    ``n`` seeds'."""
    rs = counts["plastic"]["runs"]
    return real_robot_entry(
        {
            "obstacle seen to the end approached": (
                PAPER_END_S - PAPER_SEEN_S,
                "detected an obstacle on the left (0:20 min), approached the end of the path (1:08 min)",
                [interval_s(r["seen_time_s"], r["end_time_s"]) for r in rs],
            ),
            "the end approached to out of the path": (
                PAPER_OUT_S - PAPER_END_S,
                "approached the end of the path (1:08 min), finally went out of the path (3:20 min)",
                [interval_s(r["end_time_s"], r["out_time_s"]) for r in rs],
            ),
        },
        control_hz,
        steps / control_hz,
        f"the plastic network's {n} seeds in the default geometry (the static network got stuck on the real "
        f"robot); times from the path sampled every {PATH_EVERY_S:g} s",
    )


def _geometry(arena: ArenaSpec) -> dict[str, Any]:
    """Boxes (x, y, yaw, sx, sy, h; m, rad), start, exit region and the path's key lines (m)."""
    o = arena.options
    return {
        **arena_geometry(arena),
        "open_end_x": MOUTH,
        "end_wall_x": MOUTH + o["length"],
        "right_wall_face_y": -o["width"] / 2,
        "left_obstacle_face_y": o["width"] / 2,
        "opening_m": OPENING,
    }


def draw_map(ax: Axes, res: Result, net: str) -> None:
    """Outcome map of ``net``: path width (rows) x obstacle spacing (columns), cells shaded by the share of seeds that
    got out (a colour bar beside). Each cell writes how many seeds got out (by the left side / the open end) and
    how many stayed stuck (at the dead end / in the path)."""
    s = res.summary
    f = s["sweep_factors"]
    share = np.full((len(f), len(f)), np.nan)
    for cell in s["map"]:
        i, j = f.index(cell["width_factor"]), f.index(cell["spacing_factor"])
        c = cell[net]
        share[i, j] = c["got_out"] / c["seeds"]
        stuck = c["seeds"] - c["got_out"]
        text = (
            f"out {c['got_out']}/{c['seeds']} (side {c[OUT_LEFT]}, end {c[OUT_END]})\n"
            f"stuck {stuck} (dead end {c[STUCK_END]}, path {c[STUCK_PATH]})"
        )
        ax.text(j, i, text, ha="center", va="center", fontsize=FONT["small"])
    im = ax.imshow(share, cmap="RdYlGn", vmin=0, vmax=1, origin="lower", alpha=0.6, aspect="auto")
    colorbar(im, ax, "share of seeds out", ticks=(0, 0.5, 1))
    o = s["map"][0]["arena_opts"]
    widths = sorted({c["arena_opts"]["width"] for c in s["map"]})
    spacings = sorted({c["arena_opts"]["spacing"] for c in s["map"]})
    ax.set_xticks(range(len(f)), [f"{x:.2f}" for x in spacings])
    ax.set_yticks(range(len(f)), [f"{x:.3f}" for x in widths])
    ax.set(
        xlabel="obstacle spacing (m)",
        ylabel="path width (m)",
        title=f"{net}: outcome map ({o['length']} m path, {s['steps'] / s['control_hz']:.0f} s at "
        f"{s['control_hz']:g} Hz)",
    )


@styled
def plot(res: Result) -> Figure:
    """A-B: snapshot strips (plastic, static); C-D: top views of every seed's path; E-F: outcome maps (where the
    geometry was swept; a single cell is the runs of C-D again and is left out); then the examples' steering and
    weights. One row per subfigure."""
    plt = pyplot()
    s, a = res.summary, res.arrays
    arena = make_arena(s["arena"], **s["arena_opts"])
    swept = len(s.get("sweep_factors", [])) > 1
    ratios = [1.1, 1.1, 2.5, 2.2, 2.6] if swept else [1.1, 1.1, 2.5, 2.6]
    fig = plt.figure(figsize=(17, 2 * sum(ratios)), layout="constrained")
    rows = fig.subfigures(len(ratios), 1, height_ratios=ratios)
    paths, traces = rows[2].add_gridspec(1, 2), rows[-1].add_gridspec(1, 2)
    letters = iter("CDEFGH" if swept else "CDEF")
    for row, net in enumerate(NETWORKS):
        c, ex = s["counts"][net], s["example"][net]
        when = f" at {ex['out_time_s']:.0f} s" if ex["out_time_s"] is not None else ""
        axes = list(rows[row].subplots(1, N_SNAPSHOTS))
        label = f"{net}, seed {ex['seed']}: {ex['outcome']}{when}"
        draw_strip(axes, a[f"{net}/frames"], list(a[f"{net}/snapshot_t"]), label, "AB"[row])
    panels = []
    for row, net in enumerate(NETWORKS):
        c, ex = s["counts"][net], s["example"][net]
        ax = rows[2].add_subplot(paths[0, row])
        draw_paths(
            ax,
            arena,
            [a[f"{net}/path/{k}"] for k in range(c["seeds"])],
            [r["got_out"] for r in c["runs"]],
            a[f"{net}/example/pose"],
            f"{net}: got out {c['got_out']}/{c['seeds']} seeds",
            t=a[f"{net}/example/t"],
            outcomes=("got out", "stuck"),
        )
        panels.append(ax)
    if swept:
        maps = rows[3].add_gridspec(1, 2)
        for row, net in enumerate(NETWORKS):
            ax = rows[3].add_subplot(maps[0, row])
            draw_map(ax, res, net)
            panels.append(ax)
    for row, net in enumerate(NETWORKS):
        e = {k: a[f"{net}/example/{k}"] for k in ("t", "outputs", "b", "q")}
        label = f"{net}, seed {s['example'][net]['seed']}"
        panels.append(draw_traces(rows[-1], traces[0, row], e["t"], e["outputs"], e["b"], e["q"], label))
    for ax in panels:
        letter(ax, next(letters))
    fig.suptitle(verdict_title(s))
    return fig


def verdict_title(s: dict[str, Any]) -> str:
    """The picture's title: the counts, and the verdicts the report gives them (its judge's, the one rule)."""
    plastic, static = claims(s, bool(s.get("quick")))[:2]
    p, st = s["counts"]["plastic"], s["counts"]["static"]
    return (
        f"Complex path (paper Fig. 9): got out of the path plastic {p['got_out']}/{p['seeds']}, static "
        f"{st['got_out']}/{st['seeds']} in {s.get('duration_s', 0):g} s\n(the report's verdicts: plastic goes out, "
        f"{plastic.verdict}; static gets stuck over {STUCK_WINDOW_STEPS:,} control steps, {static.verdict})"
    )


#: The window of "the static robot gets stuck", in control steps: the paper shows its static robot stuck while its
#: plastic one goes out, at 3:20 min (:data:`PAPER_OUT_S`) on a controller of 27 Hz; its videos do not say how long
#: the static one was watched. Stuck is judged over as many control steps as the real plastic robot needed to get
#: out (the networks' time is counted in steps: the same window at 10 Hz and at 27 Hz).
STUCK_WINDOW_STEPS = round(PAPER_OUT_S * 27.0)
WINDOWS_STEPS = (1000, 2000, 3000, 4000, STUCK_WINDOW_STEPS, 6000, 7000, STEPS)
"""Windows (control steps) at which the static network's share still in the path is reported: where it flips."""


def still_in(st: dict[str, Any], hz: float, steps: int) -> int | None:
    """How many of the static network's runs ``st`` (``counts["static"]``, its ``runs`` with ``out_time_s``) were
    still in the path after ``steps`` control steps at ``hz``; None where the runs ended sooner."""
    runs = st.get("runs") or []
    if not runs or steps > round(max(float(st.get("duration_s", 0.0)), 0.0) * hz):
        return None
    return sum(r["out_time_s"] is None or r["out_time_s"] * hz > steps for r in runs)


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The plastic network goes out of the complex path; the static one gets stuck in it, over the paper's window
    (:data:`STUCK_WINDOW_STEPS`), with its share at every window of :data:`WINDOWS_STEPS` the runs cover; at the real
    robot's control rate also its times (:func:`~neurowalk.experiments.suites.real_robot.real_robot_claims`)."""
    p, st = s["counts"]["plastic"], s["counts"]["static"]
    hz = s.get("control_hz", SIM_HZ)
    timed = {**st, "duration_s": s.get("duration_s", 0.0)}
    at = {w: still_in(timed, hz, w) for w in WINDOWS_STEPS}
    k = at[STUCK_WINDOW_STEPS]
    stuck = outcome_claim(
        "static network gets stuck in the path (Fig. 9, Supplementary Video 2)",
        "stuck",
        st["seeds"] - st["got_out"] if k is None else k,
        st["seeds"],
    )
    curve = ", ".join(f"{w:,} steps {n}/{st['seeds']}" for w, n in at.items() if n is not None)
    window = (
        f"stuck: still in the path after {STUCK_WINDOW_STEPS:,} control steps ({STUCK_WINDOW_STEPS / hz:.0f} s at "
        f"{hz:g} Hz), the steps the paper's plastic robot took to get out (3:20 min at 27 Hz; the paper does not say "
        f"how long its static robot was watched); still in the path, by window: {curve}; "
    )
    stuck = replace(stuck, rule=window + stuck.rule)
    return [
        outcome_claim("plastic network goes out of the complex path (Fig. 9)", "out", p["got_out"], p["seeds"]),
        stuck,
        *real_robot_claims(s),
    ]
