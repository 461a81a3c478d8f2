"""Fig. 7: measured joint angles of all 18 leg joints for forward, backward, turn right, turn left.

AMOSII in MuJoCo on the open floor, steered by constant signals through the full locomotion
network (paper Table 1): forward (O1, O2) = (-1, -1), backward (1, 1), turn right (1, -1), turn
left (-1, 1). Swing phases (CTr elevated) are shaded. The json holds the numbers behind the
picture, measured from the physics: leg order of the swings, swing fraction, legs in swing at
once, gait period, speed and turning rate.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from neurowalk import anatomy, gait
from neurowalk.experiments import Result
from neurowalk.neural.cpg import period
from neurowalk.plotting import pyplot
from neurowalk.sim.episode import EpisodeConfig, run_episode

if TYPE_CHECKING:
    from matplotlib.figure import Figure

NAME = "fig7"
CONDITIONS = {"forward": (-1.0, -1.0), "backward": (1.0, 1.0), "turn right": (1.0, -1.0), "turn left": (-1.0, 1.0)}
WARMUP = 300  # control steps before the delay lines are full and the gait is steady
WINDOW = 200  # control steps shown (20 s, about 2.3 cycles)


def measured_swing(angles: np.ndarray) -> np.ndarray:
    """Swing phases from measured joint angles (CTr elevated; see gait.swing_mask_hysteresis)."""
    return gait.swing_mask_hysteresis(angles)


def run(*, quick: bool = False, seed: int = 0) -> Result:
    """Run the four conditions (1000 control steps each; 600 with ``quick``)."""
    steps = 600 if quick else 1000
    summary: dict = {"steps": steps, "control_hz": 10.0, "warmup_steps": WARMUP, "seed": seed, "conditions": {}}
    arrays: dict[str, np.ndarray] = {}
    for i, (name, steer) in enumerate(CONDITIONS.items()):
        ep = run_episode(EpisodeConfig(controller="fixed", steer=steer, steps=steps, seed=seed))
        tr, s = ep.trajectory, ep.summary
        angles = tr.joint_angles[WARMUP:]
        swing = measured_swing(angles)
        duration = (steps - WARMUP) / 10.0
        pose = tr.pose[WARMUP:]
        fwd = (pose[-1, :2] - pose[0, :2]) @ np.array([np.cos(pose[0, 2]), np.sin(pose[0, 2])])
        yaw = np.unwrap(pose[:, 2])
        summary["conditions"][name] = {
            "steer": list(steer),
            "leg_order": gait.leg_sequence(swing),
            "swing_fraction_per_leg": dict(zip(anatomy.LEGS, swing.mean(axis=0).round(4).tolist(), strict=True)),
            **gait.duty_summary(swing),
            "stroke_direction": dict(zip(anatomy.LEGS, gait.stroke_direction(angles, swing).tolist(), strict=True)),
            "period_s": period(angles[:, anatomy.CTR_INDICES[2]] - angles[:, anatomy.CTR_INDICES[2]].mean()) / 10.0,
            "speed_m_per_s": fwd / duration,
            "turning_rate_deg_per_s": float(np.degrees(yaw[-1] - yaw[0]) / duration),
            "min_up_z": s["min_up_z"],
            "simulation_warnings": s["simulation_warnings"],
        }
        arrays[f"c{i}_angles"] = angles[:WINDOW]
        arrays[f"c{i}_swing"] = swing[:WINDOW]
    return Result(NAME, summary, arrays)


def plot(res: Result) -> Figure:
    """Four columns (A-D), 18 stacked joint traces each (degrees), swing phases shaded grey."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 4, figsize=(16, 10), sharey=True, constrained_layout=True)
    rows = [(j, leg) for leg in anatomy.LEGS for j in anatomy.LEG_JOINTS]
    for i, (name, ax) in enumerate(zip(res.summary["conditions"], axes, strict=True)):
        ang = np.degrees(res.arrays[f"c{i}_angles"])
        sw = res.arrays[f"c{i}_swing"].astype(bool)
        t = np.arange(ang.shape[0]) / 10.0
        for r, (j, leg) in enumerate(rows):
            k = anatomy.joint_index(j, leg)
            y = ang[:, k]
            span = max(np.ptp(y), 1.0)
            base = -r * 1.2
            li = anatomy.LEGS.index(leg)
            ax.fill_between(t, base - 0.5, base + 0.5, where=sw[:, li], color="0.85", step="mid", lw=0)
            ax.plot(t, base + (y - y.mean()) / span, color=f"C{'TCF'.index(j[0])}", lw=1.0)
            if i == 0:
                ax.text(-0.5, base, f"{anatomy.actuator_name(j, leg)}", ha="right", va="center", fontsize=8)
            ax.text(t[-1] + 0.3, base, f"{np.ptp(y):.0f}°", va="center", fontsize=6, color="0.4")
        c = res.summary["conditions"][name]
        rates = f"{c['speed_m_per_s'] * 100:+.1f} cm/s, {c['turning_rate_deg_per_s']:+.2f} °/s"
        ax.set_title(f"{'ABCD'[i]}  {name}  {tuple(c['steer'])}\n{rates}; order {' '.join(c['leg_order'])}", fontsize=9)
        ax.set_xlabel("time (s)")
        ax.set_yticks([])
    fig.suptitle("Joint angles (each trace scaled to its range, printed right); grey: swing phase (CTr elevated)")
    return fig
