"""Table 1: the walking direction for each sign of the sensory network's outputs, and speed against amplitude.

The paper's Table 1: (O1, O2) both negative: forward; both positive: backward; O1 negative, O2 positive: turn left;
O1 positive, O2 negative: turn right; both zero: stop; "the amplitude determines the walking speed". Here the
physics AMOSII on the open floor is steered by constant outputs (controller ``fixed``) through the whole
locomotion network: every sign pair of {-1, 0, 1}^2 (nine runs), and forward walking at amplitudes 0 to 1
(O1 = O2 = -a). Each run's first :data:`WARMUP` control steps (the delay lines filling) are left out of the
measures: speed along the start heading (m/s) and turning rate (deg/s, positive: left), both per second of
simulated time at the run's control rate. A run's direction is named from them by :func:`direction`.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.lines import Line2D

from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study_runs import Kept, Term
from neurowalk.plotting.style import FONT, LINE, letter_panels, pyplot, styled
from neurowalk.sim.episode import Episode, EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "table1"
WARMUP = 300  # control steps before the delay lines are full and the gait is steady
#: The paper's Table 1: (sign of O1, sign of O2) -> walking direction.
PAPER = {
    (-1, -1): "forward",
    (1, 1): "backward",
    (-1, 1): "turn left",
    (1, -1): "turn right",
    (0, 0): "stop",
}
MOVING = 0.002  # m/s: slower than this (and turning slower than TURNING) is standing still
TURNING = 0.5  # deg/s: a turn is at least this fast and faster (in deg/s) than 100x the speed (in m/s)
DIRECTION_RULE = (  # :func:`direction` in words, for the claims' rules
    f"named by Table 1's rule (stop: under {100 * MOVING:g} cm/s and {TURNING:g} deg/s; a turn: over {TURNING:g} "
    "deg/s and over 100x the speed in m/s; else forward or backward)"
)


def direction(speed: float, turn_rate: float) -> str:
    """The walking direction of a run from its speed along the start heading (m/s) and turning rate (deg/s).

    ``stop`` where neither moves (:data:`MOVING`, :data:`TURNING`); a turn where the rotation dominates (turn rate
    in deg/s over 100 times the speed in m/s: 1 deg/s against 1 cm/s); else forward or backward by the sign of the
    speed.
    """
    if abs(speed) < MOVING and abs(turn_rate) < TURNING:
        return "stop"
    if abs(turn_rate) >= TURNING and abs(turn_rate) > 100 * abs(speed):
        return "turn left" if turn_rate > 0 else "turn right"
    return "forward" if speed > 0 else "backward"


def pace(pose: np.ndarray, control_hz: float) -> tuple[float, float]:
    """Speed along the first row's heading (m/s) and turning rate (deg/s, positive left) of a (T, 3) pose (x m, y m,
    yaw rad) sampled at ``control_hz``: from its first row to its last."""
    seconds = (len(pose) - 1) / control_hz
    heading = np.array([np.cos(pose[0, 2]), np.sin(pose[0, 2])])
    speed = float((pose[-1, :2] - pose[0, :2]) @ heading / seconds)
    turn = float(np.degrees(np.sum(np.diff(np.unwrap(pose[:, 2])))) / seconds)
    return speed, turn


def keep_walk(ep: Episode) -> dict[str, Any]:
    """A constant-steer run's pose (T - :data:`WARMUP`, 3) after the warm-up."""
    return {"pose": ep.trajectory.pose[WARMUP:]}


WALK = Term("walk", keep_walk, arrays={"pose": "float64"})
SIGNS = tuple((a, b) for a in (-1, 0, 1) for b in (-1, 0, 1))  # (sign of O1, sign of O2)
AMPLITUDES = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0)


def runs(s: Settings) -> Iterator[Plan]:
    """Nine sign pairs (``("signs", O1, O2)``) and six amplitudes of forward steering (``("amplitude", a)``), 600
    control steps each (quick: 450)."""
    steps = 450 if s.quick else 600
    for s1, s2 in SIGNS:
        yield Plan(("signs", s1, s2), _walk((float(s1), float(s2)), steps, s.seed), (WALK,))
    for a in AMPLITUDES:
        yield Plan(("amplitude", a), _walk((-a, -a), steps, s.seed), (WALK,))


def _walk(steer: tuple[float, float], steps: int, seed: int) -> EpisodeConfig:
    return EpisodeConfig(controller="fixed", steer=steer, steps=steps, seed=seed)


def _measured(run: Kept, control_hz: float) -> tuple[dict, np.ndarray]:
    """Speed (m/s), turning rate (deg/s) and direction after the warm-up of one constant-steer run, and its (T, 2)
    path."""
    pose = run.kept["walk"]["pose"]
    speed, turn = pace(pose, control_hz)
    return {"speed_m_per_s": speed, "turn_rate_deg_per_s": turn, "direction": direction(speed, turn)}, pose[:, :2]


def measure(s: Settings, runs: Mapping[tuple, Sequence[Kept]]) -> Result:
    """Each run's speed, turning rate and walking direction; the paths of the sign pairs."""
    signs, arrays = [], {}
    for i, (s1, s2) in enumerate(SIGNS):
        m, arrays[f"path{i}"] = _measured(runs["signs", s1, s2][0], s.rate)
        signs.append({"O1": s1, "O2": s2, **m, "paper": PAPER.get((s1, s2))})
    speeds = [{"amplitude": a, **_measured(runs["amplitude", a][0], s.rate)[0]} for a in AMPLITUDES]
    summary = {
        "steps": 450 if s.quick else 600,
        "warmup_steps": WARMUP,
        "control_hz": s.rate,
        "seed": s.seed,
        "signs": signs,
        "amplitude": speeds,
        "rule": {"moving_m_per_s": MOVING, "turning_deg_per_s": TURNING, "turn_over_speed": 100},
        "notes": "speed along the start heading and turning rate (positive: left) after the warm-up",
    }
    return Result(NAME, summary, arrays)


#: Colour of each measured walking direction.
DIRECTION_COLOURS = {
    "forward": "#1B9E77",
    "backward": "#D95F02",
    "turn left": "#7570B3",
    "turn right": "#E7298A",
    "stop": "0.4",
}
SCALE = 3.0  # the paths are drawn 3x


@styled
def plot(res: Result) -> Figure:
    """A: the nine paths on a grid of the signs of O1 (rows) and O2 (columns), coloured by the measured direction,
    each named by it (and by the paper's, where the paper names one); B: speed against amplitude."""
    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(14, 6.5), layout="constrained", gridspec_kw={"width_ratios": [1.1, 1]})
    s = res.summary
    differ = False
    ends = [np.array([[-0.45, -0.5], [1.65, 1.6]])]  # the grid, its labels and the scale bar
    for i, row in enumerate(s["signs"]):
        path = SCALE * (res.arrays[f"path{i}"] - res.arrays[f"path{i}"][0])
        x0, y0 = 0.6 * (row["O2"] + 1), -0.6 * (row["O1"] - 1)  # a 3 x 3 grid: O1 down, O2 across
        colour = DIRECTION_COLOURS.get(row["direction"], "k")
        ax.plot(x0 + path[:, 0], y0 + path[:, 1], lw=LINE["thick"], color=colour)
        ends.append(path[:, :2] + (x0, y0))
        ax.plot(x0, y0, "o", color="k", ms=4, zorder=3)
        ok = row["paper"] is None or row["paper"] == row["direction"]
        differ |= not ok
        label = row["direction"] + ("" if row["paper"] is None else f"\n(paper: {row['paper']})")
        ax.text(x0, y0 - 0.12, label, ha="center", va="top", fontsize=FONT["note"], color="k" if ok else "red")
    ax.plot([-0.3, -0.3 + SCALE * 0.1], [-0.38, -0.38], "k-", lw=2.5)
    ax.text(-0.3 + SCALE * 0.05, -0.36, "10 cm", ha="center", va="bottom", fontsize=FONT["note"])
    ax.set_aspect("equal")
    lo, hi = np.vstack(ends).min(axis=0) - 0.05, np.vstack(ends).max(axis=0) + 0.05
    ax.set(xlim=(lo[0], hi[0]), ylim=(lo[1], hi[1]))
    ax.set_xticks([0.0, 0.6, 1.2], ["-1", "0", "+1"])
    ax.set_yticks([1.2, 0.6, 0.0], ["-1", "0", "+1"])
    ax.set(xlabel="steering O2 (right neuron)", ylabel="steering O1 (left neuron)")
    handles = [Line2D([], [], color=c, lw=LINE["thick"], label=d) for d, c in DIRECTION_COLOURS.items()]
    handles.append(Line2D([], [], ls="none", marker="o", color="k", ms=4, label="start, heading +x"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, title="measured")
    note = "; red: not the paper's direction" if differ else ""
    ax.set_title(f"paths by the signs of (O1, O2), drawn {SCALE:g}x, {s['steps'] / s['control_hz']:g} s each{note}")
    amp = [r["amplitude"] for r in s["amplitude"]]
    bx.plot(amp, [100 * r["speed_m_per_s"] for r in s["amplitude"]], "o-", color="k")
    bx.set_xlabel("amplitude a (O1 = O2 = -a)")
    bx.set_ylabel("forward speed (cm/s)")
    bx.set_title("the amplitude sets the walking speed")
    letter_panels([ax, bx])
    fig.suptitle(
        f"Table 1: walking direction from the sensory network's outputs (physics AMOSII, {s['control_hz']:g} Hz)"
    )
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Each sign pair of the paper's Table 1 walks in the paper's direction; the amplitude sets the speed."""
    claims = []
    for row in s["signs"]:
        if row["paper"] is None:
            continue
        claims.append(
            holds(
                f"outputs ({row['O1']:+d}, {row['O2']:+d}) walk {row['paper']}",
                row["paper"],
                row["direction"] == row["paper"],
                row["direction"],
                f"{100 * row['speed_m_per_s']:.2f} cm/s along the start heading, {row['turn_rate_deg_per_s']:.2f} "
                f"deg/s turning (positive left) after the warm-up, {DIRECTION_RULE}",
            )
        )
    speeds = [r["speed_m_per_s"] for r in s["amplitude"]]
    rising = bool(np.all(np.diff(speeds) > 0))
    claims.append(
        holds(
            "the amplitude determines the walking speed",
            "speed rises with |O|",
            rising,
            [round(100 * v, 2) for v in speeds],
            f"forward speed (cm/s) at amplitudes {[r['amplitude'] for r in s['amplitude']]}: "
            + ("rises at every step" if rising else "does not rise at every step"),
            unit="cm/s, at |O| rising",
        )
    )
    return claims
