"""Judges of the results that need no arena: Table 1 (directions), Fig. 2 (dynamics), Fig. 4 (weights), Fig. 7.

A judge reads a figure's saved numbers (its ``FIG.json`` summary) and returns the paper's results it shows as
:class:`~neurowalk.experiments.reproduce.claims.Claim` s; ``quick`` says the figure was run with ``--quick``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from neurowalk.experiments.reproduce.claims import Claim, holds, value

#: Fig. 7's caption: in the wave gait "the legs swing one by one from hind to front".
HIND_TO_FRONT = (("R3", "R2", "R1"), ("L3", "L2", "L1"))


def table1(s: dict[str, Any], quick: bool) -> list[Claim]:
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
                f"deg/s turning (positive left) after the warm-up, named by figures.table1.direction",
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
        )
    )
    return claims


def fig2(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Single neuron: linear for small b, a hysteresis for larger b, its width growing with b; the static
    network's b = 2.4, c = -3.5 has a hysteresis; the strong weights latch (permanent turning)."""
    single = s["single_neuron"]
    small = [r for r in single if r["b"] < 1.0]
    larger = [r for r in single if r["b"] > 1.0 and not r["latched"]]
    widths = [r["width"] for r in larger]
    static, strong = s["two_neuron_loops"][0], s["two_neuron_loops"][-1]
    return [
        holds(
            "single neuron, small self-connection b < 1: no hysteresis (Fig. 2B)",
            "approximately linear I-O",
            all(r["width"] < 1e-6 for r in small),
            max(r["width"] for r in small),
            f"largest hysteresis width for b < 1 (input units): {max(r['width'] for r in small):.2g}",
        ),
        holds(
            "single neuron, b > 1: a hysteresis (Fig. 2C) whose width grows with b",
            "hysteresis, width proportional to b",
            len(widths) > 1 and all(w > 0 for w in widths) and bool(np.all(np.diff(widths) > 0)),
            [round(w, 3) for w in widths],
            f"widths at b = {[r['b'] for r in larger]}",
        ),
        holds(
            f"static network b = {static['b']}, c = {static['c']}: a hysteresis, not latched",
            "hysteresis interval (Fig. 2C)",
            static["width"] is not None and static["width"] > 0 and not static["latched"],
            static["width"],
            f"width {static['width']} of the input range [-1, 1]",
        ),
        holds(
            f"strong weights b = {strong['b']}, c = {strong['c']}: two states, the active one kept (Fig. 2D)",
            "permanent turning (active state)",
            bool(strong["latched"]),
            "latched" if strong["latched"] else f"width {strong['width']}",
            "latched: switched on and never off within the input range",
        ),
    ]


def fig4(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Constant inputs: b1, c1 converge to values independent of the start while b2, c2 stay; changing inputs:
    fast rises on a reflex, slow decay after."""
    a = s["panel_a"]
    paper = a["starts"][0]
    change = max(abs(paper["b2"] - paper["b0"]) / paper["b0"], abs(paper["q2"] - paper["q0"]) / paper["q0"])
    b = s["panel_b"]
    return [
        holds(
            "constant inputs: b1 and c1 converge to the same values from every start (Fig. 4A)",
            "converge, independent of the initial conditions",
            max(a["max_b1_rel_error"], a["max_q1_rel_error"]) < 1e-3,
            {"b1": round(s["fixed_points"]["b"], 4), "|c1|": round(s["fixed_points"]["q"], 4)},
            f"{len(a['starts'])} starts after {a['steps']} steps: largest relative distance to the fixed point "
            f"{max(a['max_b1_rel_error'], a['max_q1_rel_error']):.1e} (below 1e-3 counts as converged)",
        ),
        value(
            "constant inputs: b2 and c2 (inactive input) remain unchanged (Fig. 4A)",
            0.0,
            100 * change,
            5.0,
            unit="%",
        ),
        holds(
            "changing inputs: weights rise fast on a reflex and decay slowly after (Fig. 4B)",
            "fast rise, slow decay",
            b["growth_to_decay_ratio"] > 1,
            round(b["growth_to_decay_ratio"], 1),
            f"mean rise per step with the reflex on over mean decay per step with it off, over {b['steps']} steps",
        ),
    ]


def fig7(s: dict[str, Any], quick: bool) -> list[Claim]:
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
                " ".join(order),
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
            )
        )
    return claims
