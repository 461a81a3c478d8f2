"""Fig. 10: walking, climbing and wall avoidance on the climbing track (paper §3, third experiment).

One example run (step 0.06 m, the given seed) is drawn in full: top and side views of the path,
the backbone angle, the foot contacts and the steering over time, and rendered snapshots at the key
moments (start, first climb, wall avoidance, second climb). The outcome table runs ``seeds`` seeds
(default 10; 3 with ``quick``) at each step height of
:data:`~neurowalk.experiments.suites.climbing.TRACK_HEIGHTS` (at a rate other than the simulator's 10 Hz, the
example's height only: those rates are for the real-robot comparison), through the resumable store ``track.sqlite``
in the output folder; the success rule is in the json. Every run lasts at most
:data:`~neurowalk.experiments.suites.climbing.TRACK_STEPS` control steps at the control rate ``control_hz`` (10 Hz
by default, the authors' simulator; 27 Hz is the real robot's: as many steps, the networks' time); it stops once on
the second platform. The json's ``real_robot`` entry puts the paper's intervals between its photos (climbing onto the
first platform 0:17-0:23 min, onto the second at 1:14 min, with the controller at 27 Hz) beside the simulated
ones.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.patches import Polygon

from neurowalk import anatomy
from neurowalk.arenas import make_arena
from neurowalk.body.registry import body_model
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, outcome
from neurowalk.experiments.study_runs import Kept, Term
from neurowalk.experiments.suites.climbing import (
    FIRST_PLATFORM,
    TRACK_HEIGHTS,
    TRACK_RULE,
    TRACK_STEPS,
    climb_step,
    track_spec,
    track_success,
)
from neurowalk.experiments.suites.real_robot import real_robot_claims
from neurowalk.experiments.suites.timing import SIM_HZ, interval_s, real_robot_entry
from neurowalk.plotting import draw_arena
from neurowalk.plotting.style import (
    FONT,
    LINE,
    SIDE_COLOURS,
    legend_outside,
    letter_panels,
    pyplot,
    styled,
    time_colorbar,
)
from neurowalk.render import render_frames
from neurowalk.sim.config import EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from neurowalk.sim.episode import Episode

MOMENTS: tuple[str, ...] = ("start", "first climb", "wall avoidance", "second climb")
ARRAYS = ("t", "pose", "z", "bj_command", "bj_angle", "foot_contact", "outputs")  # the example's traces drawn
MOMENT_COLOUR = "#D62728"  # the key moments' dashed lines and numbers
PAPER_CLIMB_S = 17.0  # the real robot detected the platform and climbed onto it at 0:17-0:23 min (paper §3, Fig. 10)
PAPER_FIRST_S = 23.0  # on the first platform at 0:23 min
PAPER_SECOND_S = 74.0  # and onto the second platform at 1:14 min


def key_moments(bj_command: np.ndarray, outputs: np.ndarray) -> dict[str, int | None]:
    """Control steps of the key moments of a track run from the backbone command (T,) rad and steering (T, 2).

    A climb is the first step the backbone leans down (:func:`~neurowalk.experiments.suites.climbing.climb_step`:
    front legs on the step, rear segment being lifted); wall avoidance is the first strong turn (|O1 - O2| > 1)
    after the first climb; the second climb is the first climb after that. None where it never happens.
    """

    def first(mask: np.ndarray, after: int | None) -> int | None:
        if after is None:
            return None
        idx = np.flatnonzero(mask[after:])
        return int(idx[0]) + after if len(idx) else None

    climb1 = climb_step(bj_command)
    wall = first(np.abs(outputs[:, 0] - outputs[:, 1]) > 1.0, climb1)
    climb2 = None if wall is None else climb_step(bj_command, wall)
    return {"start": 0, "first climb": climb1, "wall avoidance": wall, "second climb": climb2}


def keep_example(ep: Episode) -> dict[str, Any]:
    """What the figure draws of the example run: t (T,) s, pose (T, 3), trunk z (T,) m, the backbone's command and
    angle (T,) rad, foot contacts (T, 6), steering (T, 2), the :func:`key_moments` and the positions (4, nq) at
    them (the last step for a moment that never happened)."""
    tr = ep.trajectory
    moments = key_moments(tr.targets[:, -1], tr.outputs)
    rows = [moments[m] if moments[m] is not None else len(tr.qpos) - 1 for m in MOMENTS]
    return {
        "t": tr.t,
        "pose": tr.pose,
        "z": tr.qpos[:, 2],
        "bj_command": tr.targets[:, -1],
        "bj_angle": tr.joint_angles[:, -1],
        "foot_contact": tr.foot_contact,
        "outputs": tr.outputs,
        "moments": moments,
        "moment_qpos": tr.qpos[rows],
    }


EXAMPLE = Term("fig10 example", keep_example, arrays={k: "float64" for k in (*ARRAYS, "moment_qpos")})


def runs(s: Settings) -> Iterator[Plan]:
    """The outcome table's runs over the seeds per step height (``(height)``), the first of step 0.06 m (seed
    ``seed``) the example, kept in full."""
    for h in TRACK_HEIGHTS if s.rate == SIM_HZ else TRACK_HEIGHTS[:1]:  # the first only for the real-robot rates
        for k in range(s.n(10, 3)):
            first = h == TRACK_HEIGHTS[0] and k == 0
            cfg = EpisodeConfig.from_spec(track_spec(h, s.seed + k, TRACK_STEPS, control_hz=s.rate))
            yield Plan(h, cfg, (FIRST_PLATFORM, EXAMPLE) if first else (FIRST_PLATFORM,))


def measure(s: Settings, runs: Mapping[float, Sequence[Kept]]) -> Result:
    """The example run (step 0.06 m, seed ``seed``): its key moments and their snapshots; the outcome table (see the
    module doc)."""
    step = TRACK_HEIGHTS[0]
    ex = runs[step][0]
    control_hz, steps, n = ex.config.control_hz, ex.config.steps, len(runs[step])
    kept = ex.kept["fig10 example"]
    moments = kept["moments"]
    arena = make_arena("climbing-track", step=step)
    table = {f"{h:.2f}": _height_row(rs, h, s.seed, control_hz) for h, rs in runs.items()}
    summary = {
        "step_m": step,
        "seed": s.seed,
        "steps": steps,
        "control_hz": float(control_hz),
        "duration_s": steps / control_hz,
        "variant": s.variant or "paper",
        "rule": TRACK_RULE,
        "moments": moments,
        "moments_s": {m: _seconds(k, control_hz) for m, k in moments.items()},
        "example": {
            **{k: _json(getattr(ex, k)) for k in ("exit_step", "max_z_m", "final_z_m", "final_pose")},
            "first_platform_step": ex.kept["first_platform"]["first_platform_step"],
        },
        "table": table,
        "arena": arena.options,
        "real_robot": _real_robot(table[f"{step:.2f}"]["runs"], n, step, steps, control_hz),
    }
    return Result("fig10", summary, {**{k: kept[k] for k in ARRAYS}, "moment_qpos": kept["moment_qpos"]})


def render(res: Result) -> dict[str, np.ndarray]:
    """The snapshots at the key moments (``frames``), rendered from their recorded positions (``moment_qpos``)."""
    arena = make_arena("climbing-track", step=res.summary["step_m"])
    model = body_model("amosii", arena)
    return {"frames": render_frames(model, res.arrays["moment_qpos"], distance=1.4, elevation=-50.0, centred=True)}


def _json(v: Any) -> Any:
    """A summary's value as JSON has it (tuples as lists)."""
    return list(v) if isinstance(v, tuple) else v


def _seconds(k: int | None, control_hz: float) -> float | None:
    """Time (s) of control step ``k`` at ``control_hz`` Hz (None: it never happened)."""
    return None if k is None else k / control_hz


def _height_row(kept: Sequence[Kept], h: float, seed: int, control_hz: float) -> dict:
    """The outcome table's row of step height ``h`` (m) from its seeds' stored runs ``kept`` (seeds ``seed``, ...):
    successes, each run (steps and times in s) and the median time to the second platform."""
    runs = [{**r.summary.to_dict(), **r.kept["first_platform"]} for r in kept]  # each with its first_platform_step
    ok = [track_success(r, h) for r in runs]
    done = [r["exit_step"] for r in runs if r["exit_step"] is not None]
    return {
        "seeds": len(runs),
        "success": int(sum(ok)),
        "runs": [
            {
                "seed": seed + k,
                "success": bool(o),
                "exit_step": r["exit_step"],
                "exit_time_s": _seconds(r["exit_step"], control_hz),
                "first_platform_step": r["first_platform_step"],
                "first_platform_time_s": _seconds(r["first_platform_step"], control_hz),
                "detected_time_s": _seconds(r["detected_step"], control_hz),
                "max_z_m": r["max_z_m"],
            }
            for k, (o, r) in enumerate(zip(ok, runs, strict=True))
        ],
        "median_exit_step": float(np.median(done)) if done else None,
        "median_exit_time_s": float(np.median(done)) / control_hz if done else None,
    }


def _real_robot(first: list[dict], n: int, step: float, steps: int, control_hz: float) -> dict:
    """The paper's intervals (climbing onto the first platform; from it to the second) beside those of the ``n``
    seeds at step ``step`` m (their table rows ``first``)."""
    return real_robot_entry(
        {
            "platform detected to on it": (
                PAPER_FIRST_S - PAPER_CLIMB_S,
                "detected the platform as a climbable obstacle and climbed onto it (0:17-0:23 min)",
                [interval_s(r["detected_time_s"], r["first_platform_time_s"]) for r in first],
            ),
            "the first platform to the second": (
                PAPER_SECOND_S - PAPER_FIRST_S,
                "on the first platform (0:23 min), after avoiding the wall climbed onto the second (1:14 min)",
                [interval_s(r["first_platform_time_s"], r["exit_time_s"]) for r in first],
            ),
        },
        control_hz,
        steps / control_hz,
        f"the {n} seeds at step {step} m; on a platform: the trunk centre 0.3 m past its edge; detected: the "
        "backbone leans up for a climbable step ahead",
    )


def _draw_track(ax: Axes, arena_opts: dict, pose: np.ndarray, t: np.ndarray) -> None:
    """Top view: floors shaded by height (a legend of the heights), walls dark, the path coloured by time (s) with
    a colour bar."""
    arena = make_arena("climbing-track", **arena_opts)
    path = draw_arena(ax, arena, pose, t=t)
    top = max(b.h for b in arena.boxes)
    seen: set[float] = set()
    for b in sorted(arena.boxes, key=lambda b: b.h):
        wall = b.h >= top - 1e-9
        colour = "0.15" if wall else (0.95 - 3.0 * b.h, 0.85 - 3.5 * b.h, 0.7 - 3.5 * b.h)
        label = None
        if round(b.h, 3) not in seen:
            seen.add(round(b.h, 3))
            label = "wall" if wall else f"floor {b.h * 100:.0f} cm up"
        ax.add_patch(Polygon(b.corners(), closed=True, color=colour, zorder=1.2 if wall else 1.1, label=label))
    if path is not None:
        time_colorbar(path, ax)
    legend_outside(ax, side="below", ncol=2, fontsize=FONT["small"])


def _moment_lines(ax: Axes, t: np.ndarray, moments: dict[str, int | None]) -> None:
    """A dashed line at each key moment on a time axes, numbered inside its top as the snapshots are."""
    for n, name in enumerate(MOMENTS, start=1):
        k = moments.get(name)
        if k is None:
            continue
        ax.axvline(t[k], color=MOMENT_COLOUR, lw=LINE["trace"], ls="--", zorder=3)
        ax.annotate(
            str(n),
            (t[k], 1.0),
            xycoords=("data", "axes fraction"),
            xytext=(2, -2),
            textcoords="offset points",
            ha="left",
            va="top",
            fontsize=FONT["note"],
            fontweight="bold",
            color=MOMENT_COLOUR,
            bbox={"boxstyle": "round,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.85},
            zorder=4,
        )


@styled
def plot(res: Result) -> Figure:
    """A: top view; B: side view; C: backbone angle; D: foot contacts; E: steering; F: the four key moments'
    snapshots, numbered as the dashed lines on C-E. One row per subfigure."""
    plt = pyplot()
    s, a = res.summary, res.arrays
    t = a["t"]
    fig = plt.figure(figsize=(16, 13.5), layout="constrained")
    rows = fig.subfigures(3, 1, height_ratios=[1.35, 0.95, 0.95])
    grid = rows[0].add_gridspec(1, 4, width_ratios=[1.15, 1, 1.1, 1.1])
    top = rows[0].add_subplot(grid[0, 0])
    _draw_track(top, s["arena"], a["pose"], t)
    top.set_title(f"top view (step {s['step_m'] * 100:g} cm, seed {s['seed']})")
    side = rows[0].add_subplot(grid[0, 1])
    path = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(a["pose"][:, :2], axis=0).T))])
    side.plot(path, a["z"], lw=LINE["trace"], color="k")
    side.set(xlabel="path length (m)", ylabel="trunk height (m)", title="side view")
    bj = rows[0].add_subplot(grid[0, 2:])
    bj.plot(t, np.degrees(a["bj_command"]), lw=LINE["trace"], color="C0", label="command")
    bj.plot(t, np.degrees(a["bj_angle"]), lw=LINE["trace"], color="C1", alpha=0.7, label="measured")
    bj.set(xlabel="time (s)", ylabel="backbone angle (°, + up)", title="backbone joint")
    legend_outside(bj, side="below", ncol=2)
    grid = rows[1].add_gridspec(1, 2)
    feet = rows[1].add_subplot(grid[0, 0])
    feet.imshow(
        a["foot_contact"].T > 0.5, aspect="auto", interpolation="nearest", cmap="Greys", extent=(t[0], t[-1], 5.5, -0.5)
    )
    feet.set(yticks=range(6), yticklabels=anatomy.LEGS, xlabel="time (s)", ylabel="leg")
    feet.set_title("foot contacts (black: on the ground)")
    steer = rows[1].add_subplot(grid[0, 1], sharex=feet)
    steer.plot(t, a["outputs"][:, 0], color=SIDE_COLOURS["left"], lw=LINE["trace"], label="O1 (left)")
    steer.plot(t, a["outputs"][:, 1], color=SIDE_COLOURS["right"], lw=LINE["trace"], label="O2 (right)")
    steer.set(xlabel="time (s)", ylabel="steering O", yticks=(-1, 0, 1), title="steering signals")
    legend_outside(steer)
    for ax in (bj, feet, steer):
        _moment_lines(ax, t, s["moments"])
    shots = list(rows[2].subplots(1, len(MOMENTS)))
    for i, (ax, name) in enumerate(zip(shots, MOMENTS, strict=True)):
        ax.imshow(a["frames"][i])
        k = s["moments"][name]
        ax.set_title(f"{i + 1}  {name}: t = {t[k]:.0f} s" if k is not None else f"{i + 1}  {name}: did not happen")
        ax.axis("off")
    letter_panels([top, side, bj, feet, steer, shots[0]])
    ok = ", ".join(f"{float(h) * 100:g} cm: {v['success']}/{v['seeds']}" for h, v in s["table"].items())
    rate = (
        f" (runs of at most {s['steps'] / s['control_hz']:.0f} s at {s['control_hz']:g} Hz)"
        if "control_hz" in s
        else ""
    )
    fig.suptitle(f"Climbing track: reached the second platform with steps of {ok}{rate}")
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The climbing track crossed: first step climbed, wall avoided, second step climbed; at the real robot's control
    rate also its times (:func:`~neurowalk.experiments.suites.real_robot.real_robot_claims`)."""
    row = s["table"][f"{s['step_m']:.2f}"]
    return [
        outcome(
            f"climbs the first step, avoids the wall, climbs the second (steps of {s['step_m']} m; Fig. 10)",
            "crossed",
            row["success"],
            row["seeds"],
        ),
        *real_robot_claims(s),
    ]
