"""Fig. 7: measured joint angles of all 18 leg joints for forward, backward, turn right, turn left.

AMOSII in MuJoCo on the open floor, steered by constant signals through the full locomotion
network (paper Table 1): forward (O1, O2) = (-1, -1), backward (1, 1), turn right (1, -1), turn
left (-1, 1). Swing phases (CTr elevated) are shaded. The json holds the numbers behind the
picture, measured from the physics: leg order of the swings, swing fraction, legs in swing at
once, gait period, speed and turning rate. Every number comes from one window, stated in the json
(``window``): from the end of the :data:`WARMUP` control steps to the end of the run; the picture
draws the first :data:`SHOWN` control steps of it. The run's control rate ``control_hz`` (10 Hz by
default, the authors' simulator; 27 Hz is the real robot's) turns control steps into seconds: the
networks count in control steps (the CPG period is 87.5 of them), so at 27 Hz the gait is 2.7 times
as fast in seconds, and so are the speed and turning rate.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from neurowalk import anatomy, gait
from neurowalk.experiments import Plan, Result, Settings
from neurowalk.experiments.reproduce.claims import Claim, holds
from neurowalk.experiments.study_runs import Kept, Term
from neurowalk.neural.cpg import period
from neurowalk.plotting.style import FONT, LINE, letter_panels, pyplot, styled
from neurowalk.sim.episode import Episode, EpisodeConfig

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "fig7"
CONDITIONS = {"forward": (-1.0, -1.0), "backward": (1.0, 1.0), "turn right": (1.0, -1.0), "turn left": (-1.0, 1.0)}
WARMUP = 300  # control steps before the delay lines are full and the gait is steady
SHOWN = 200  # control steps drawn (about 2.3 gait cycles; 20 s at 10 Hz)


def keep_gait(ep: Episode) -> dict[str, Any]:
    """A constant-steer run's joint angles (T - :data:`WARMUP`, 19) rad and pose (T - :data:`WARMUP`, 3) after the
    warm-up."""
    return {"angles": ep.trajectory.joint_angles[WARMUP:], "pose": ep.trajectory.pose[WARMUP:]}


GAIT = Term("gait", keep_gait, arrays={"angles": "float64", "pose": "float64"})


def runs(s: Settings) -> Iterator[Plan]:
    """The four conditions (constant steering), 1000 control steps each (quick: 600)."""
    for name, steer in CONDITIONS.items():
        cfg = EpisodeConfig(controller="fixed", steer=steer, steps=600 if s.quick else 1000, seed=s.seed)
        yield Plan(name, cfg, (GAIT,))


def measure(s: Settings, runs: Mapping[str, Sequence[Kept]]) -> Result:
    """Gait numbers, speed (m/s) and turning rate (deg/s) over rows :data:`WARMUP` to the last of each run (the
    ``window`` of the json)."""
    steps, seed, control_hz = 600 if s.quick else 1000, s.seed, s.rate
    duration = (steps - 1 - WARMUP) / control_hz  # s from the window's first row to its last
    window = {
        "from_step": WARMUP,
        "to_step": steps - 1,
        "from_s": WARMUP / control_hz,
        "to_s": (steps - 1) / control_hz,
        "duration_s": duration,
        "shown_steps": SHOWN,
        "what": "every number of a condition: the rows from the end of the warm-up to the last of the run; the "
        "picture draws the first shown_steps of them",
    }
    summary: dict = {
        "steps": steps,
        "control_hz": float(control_hz),
        "warmup_steps": WARMUP,
        "window": window,
        "seed": seed,
        "conditions": {},
    }
    arrays: dict[str, np.ndarray] = {}
    for i, (name, steer) in enumerate(CONDITIONS.items()):
        run = runs[name][0]
        done = run.summary.to_dict()
        angles, pose = run.kept["gait"]["angles"], run.kept["gait"]["pose"]
        swing = gait.swing_mask_hysteresis(angles)  # swing phases: CTr elevated
        ctr3 = angles[:, anatomy.CTR_INDICES[2]]
        fwd = (pose[-1, :2] - pose[0, :2]) @ np.array([np.cos(pose[0, 2]), np.sin(pose[0, 2])])
        yaw = np.unwrap(pose[:, 2])
        summary["conditions"][name] = {
            "steer": list(steer),
            "leg_order": gait.leg_sequence(swing),
            "swing_fraction_per_leg": dict(zip(anatomy.LEGS, swing.mean(axis=0).round(4).tolist(), strict=True)),
            **gait.duty_summary(swing),
            "stroke_direction": dict(zip(anatomy.LEGS, gait.stroke_direction(angles, swing).tolist(), strict=True)),
            "period_s": period(ctr3 - ctr3.mean()) / control_hz,
            "speed_m_per_s": fwd / duration,
            "turning_rate_deg_per_s": float(np.degrees(yaw[-1] - yaw[0]) / duration),
            "min_up_z": done["min_up_z"],
            "simulation_warnings": done["simulation_warnings"],
        }
        arrays[f"c{i}_angles"] = angles[:SHOWN]
        arrays[f"c{i}_swing"] = swing[:SHOWN]
    return Result(NAME, summary, arrays)


#: Colour of each joint kind (the first letter of its name): thoraco-coxal, coxa-trochanteral, femur-tibia.
JOINT_COLOURS = {"T": "C0", "C": "C1", "F": "C2"}
JOINT_NAMES = {"T": "TC joint (+ forward)", "C": "CTr joint (+ up)", "F": "FTi joint (+ extended)"}


@styled
def plot(res: Result) -> Figure:
    """Four columns (A-D), 18 stacked joint traces each, each scaled to its range (its range in degrees written at
    its right) over time (s), swing phases shaded grey; a legend of the joint kinds below."""
    plt = pyplot()
    hz = res.summary["control_hz"]
    w = res.summary.get("window")
    fig, axes = plt.subplots(1, 4, figsize=(17, 11), sharey=True, layout="constrained")
    rows = [(j, leg) for leg in anatomy.LEGS for j in anatomy.LEG_JOINTS]
    for i, (name, ax) in enumerate(zip(res.summary["conditions"], axes, strict=True)):
        ang = np.degrees(res.arrays[f"c{i}_angles"])
        sw = res.arrays[f"c{i}_swing"].astype(bool)
        t = np.arange(ang.shape[0]) / hz
        for r, (j, leg) in enumerate(rows):
            k = anatomy.joint_index(j, leg)
            y = ang[:, k]
            span = max(np.ptp(y), 1.0)
            base = -r * 1.2
            li = anatomy.LEGS.index(leg)
            ax.fill_between(t, base - 0.5, base + 0.5, where=sw[:, li], color="0.85", step="mid", lw=0)
            ax.plot(t, base + (y - y.mean()) / span, color=JOINT_COLOURS[j[0]], lw=LINE["trace"])
            ax.text(t[-1] * 1.02, base, f"{np.ptp(y):.0f}°", va="center", fontsize=FONT["small"], color="0.35")
        c = res.summary["conditions"][name]
        rates = f"{c['speed_m_per_s'] * 100:+.1f} cm/s, {c['turning_rate_deg_per_s']:+.2f} °/s"
        steer = ", ".join(f"{v:g}" for v in c["steer"])
        ax.set_title(f"{name}, (O1, O2) = ({steer})\n{rates}\nswing order {' '.join(c['leg_order'])}")
        ax.set(xlabel="time after the warm-up (s)", xlim=(0, t[-1] * 1.1))
        ax.spines[["top", "right"]].set_visible(False)
    names = [anatomy.actuator_name(j, leg) for j, leg in rows]
    axes[0].set_yticks([-r * 1.2 for r in range(len(rows))], names, fontsize=FONT["note"])
    axes[0].set_ylabel("joint angle, each trace scaled to its range (range at its right)")
    letter_panels(axes)
    handles = [Line2D([], [], color=JOINT_COLOURS[k], lw=LINE["thick"], label=v) for k, v in JOINT_NAMES.items()]
    handles.append(Patch(color="0.85", label="swing phase (CTr elevated)"))
    fig.legend(handles=handles, loc="outside lower center", ncol=4)
    over = f"; speed and turning rate over t = {w['from_s']:.1f}-{w['to_s']:.1f} s" if w else ""
    fig.suptitle(f"Joint angles of all legs at {hz:g} Hz control{over}")
    return fig


def claims(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The wave gait: legs swing one by one from hind to front; strokes follow the walking direction."""
    claims = []
    for name, c in s["conditions"].items():
        order = tuple(c["leg_order"])
        sides = (order[:3], order[3:]) if order[0][0] == "R" else (order[3:], order[:3])
        one_by_one = c["time_two_or_more_in_swing"] <= 0.1
        claims.append(
            holds(
                f"{name}: legs swing one by one from hind to front (Fig. 7)",
                "wave gait, hind to front",
                sides == HIND_TO_FRONT and one_by_one,
                "swing order " + " ".join(order),
                f"swing order {' '.join(order)}; two or more legs in swing {c['time_two_or_more_in_swing']:.0%} of "
                "the time (one by one: at most 10%)",
            )
        )
    want = {"forward": (1, 1), "backward": (-1, -1), "turn right": (-1, 1), "turn left": (1, -1)}
    for name, (right, left) in want.items():
        d = s["conditions"][name]["stroke_direction"]
        ok = all(d[f"R{i}"] == right and d[f"L{i}"] == left for i in (1, 2, 3))
        claims.append(
            holds(
                f"{name}: stance strokes of the right and left legs (Fig. 7, TC joints)",
                f"right {'forward' if right > 0 else 'backward'} legs, left {'forward' if left > 0 else 'backward'}",
                ok,
                d,
                "sign of each leg's TC stroke (+1: the leg pushes the body forward)",
                unit="(stroke sign: +1 pushes forward)",
            )
        )
    return claims


#: Fig. 7's caption: in the wave gait "the legs swing one by one from hind to front".
HIND_TO_FRONT = (("R3", "R2", "R1"), ("L3", "L2", "L1"))
