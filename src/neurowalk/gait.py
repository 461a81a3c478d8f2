"""Gait analysis: swing phases, leg order and stroke direction from joint-angle traces.

Pure functions of arrays in actuator order (anatomy), usable on commanded targets and on
measured joint angles alike. A leg is in swing while its CTr joint is elevated above its stance
level by more than a margin.
"""

from __future__ import annotations

import numpy as np

from neurowalk import anatomy

CTR = np.array(anatomy.CTR_INDICES)
TC = np.array(anatomy.TC_INDICES)


def swing_mask(angles: np.ndarray, margin_rad: float = 0.001) -> np.ndarray:
    """(T, 6) bool, LEGS order: CTr above its own stance level (per-leg 5th percentile) + margin.

    Args:
        angles: (T, >= 18) joint angles or targets in rad, actuator order.
        margin_rad: elevation above the stance level that counts as swing.
    """
    ctr = np.asarray(angles)[:, CTR]
    stance = np.percentile(ctr, 5, axis=0)
    return ctr > stance + margin_rad


def swing_mask_hysteresis(angles: np.ndarray, low: float = 0.10, high: float = 0.30) -> np.ndarray:
    """(T, 6) swing phases of measured CTr angles, robust to small bumps during stance.

    A swing is a run of steps with the CTr elevated above stance by more than ``low`` of its
    stroke (stance level to peak, per leg) that somewhere rises above ``high`` of it.
    """
    ctr = np.asarray(angles)[:, CTR]
    stance = np.percentile(ctr, 5, axis=0)
    stroke = np.maximum(np.percentile(ctr, 99, axis=0) - stance, 1e-9)
    elev = (ctr - stance) / stroke
    out = np.zeros(ctr.shape, dtype=bool)
    for i in range(ctr.shape[1]):
        above = elev[:, i] > low
        run_id = np.cumsum(np.concatenate([[above[0]], above[1:] & ~above[:-1]])) * above
        peaks = np.zeros(run_id.max() + 1)
        np.maximum.at(peaks, run_id, elev[:, i])
        keep = peaks > high
        keep[0] = False
        out[:, i] = keep[run_id]
    return out


def swing_onsets(swing: np.ndarray) -> list[np.ndarray]:
    """Per leg (LEGS order), the step indices where a swing phase begins."""
    return [np.flatnonzero(~swing[:-1, i] & swing[1:, i]) + 1 for i in range(swing.shape[1])]


def leg_sequence(swing: np.ndarray) -> list[str]:
    """Legs in the order their swings begin within one cycle, starting after the first R3 onset.

    Returns the six leg names ordered by their first onset following R3's first onset (R3 first).
    """
    onsets = swing_onsets(swing)
    r3 = anatomy.LEGS.index("R3")
    if onsets[r3].size == 0:
        return []
    t0 = onsets[r3][0]
    first = []
    for i, leg in enumerate(anatomy.LEGS):
        later = onsets[i][onsets[i] >= t0]
        if later.size:
            first.append((later[0], leg))
    return [leg for _, leg in sorted(first)]


def stroke_direction(angles: np.ndarray, swing: np.ndarray) -> np.ndarray:
    """(6,) sign of the TC swing stroke per leg: +1 forward swing (forward walking), -1 backward.

    Compares the mean TC velocity during swing with that during stance; 0 where the leg's TC
    barely moves (peak-to-peak under 1°).
    """
    tc = np.asarray(angles)[:, TC]
    v = np.diff(tc, axis=0)
    sw = swing[1:]
    out = np.zeros(6)
    for i in range(6):
        if np.ptp(tc[:, i]) < np.deg2rad(1.0) or not sw[:, i].any() or sw[:, i].all():
            continue
        out[i] = np.sign(v[sw[:, i], i].mean() - v[~sw[:, i], i].mean())
    return out


def duty_summary(swing: np.ndarray) -> dict[str, float]:
    """Swing fraction per leg (mean) and the fractions of time with 0, 1 and >= 2 legs in swing."""
    n = swing.sum(axis=1)
    return {
        "swing_fraction": float(swing.mean()),
        "time_no_leg_in_swing": float(np.mean(n == 0)),
        "time_one_leg_in_swing": float(np.mean(n == 1)),
        "time_two_or_more_in_swing": float(np.mean(n >= 2)),
    }
