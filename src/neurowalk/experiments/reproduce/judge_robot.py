"""Judges of the real-robot experiments run in simulation: Fig. 8 (narrow passage), Fig. 9 (complex path), Fig. 10
(climbing track), at the simulator's 10 Hz (outcomes) and at the real robot's 27 Hz (times), and the step sweep.

The paper's times are those of the real AMOSII, whose controller ran at about 27 Hz (§2.2); at 27 Hz the networks
take as many steps per second as on the real robot, so the times compare, up to the body and the floor.
"""

from __future__ import annotations

from typing import Any

from neurowalk.experiments.reproduce.claims import Claim, holds, outcome, timing


def fig8(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The plastic network escapes the narrow passage; the static one stays trapped."""
    p, st = s["counts"]["plastic"], s["counts"]["static"]
    return [
        outcome("plastic network escapes the narrow passage (Fig. 8)", "escaped", p["escaped"], p["seeds"]),
        outcome(
            "static network fails to escape (Fig. 8, Supplementary Video 1)",
            "stuck",
            st["seeds"] - st["escaped"],
            st["seeds"],
        ),
    ]


def fig9(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The plastic network goes out of the complex path; the static one gets stuck in it."""
    p, st = s["counts"]["plastic"], s["counts"]["static"]
    return [
        outcome("plastic network goes out of the complex path (Fig. 9)", "out", p["got_out"], p["seeds"]),
        outcome(
            "static network gets stuck in the path (Fig. 9, Supplementary Video 2)",
            "stuck",
            st["seeds"] - st["got_out"],
            st["seeds"],
        ),
    ]


def fig10(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The climbing track crossed: first step climbed, wall avoided, second step climbed."""
    row = s["table"][f"{s['step_m']:.2f}"]
    return [
        outcome(
            f"climbs the first step, avoids the wall, climbs the second (steps of {s['step_m']} m; Fig. 10)",
            "crossed",
            row["success"],
            row["seeds"],
        )
    ]


def steps(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Beyond the paper: backbone control and the leg reflexes together climb the highest step (Fig. 10's modules,
    ablated)."""
    v = s["variants"]
    full, none = v["reflexes + backbone"]["highest_reliable_m"], v["neither"]["highest_reliable_m"]
    best = max((x["highest_reliable_m"] or 0.0) for x in v.values())
    return [
        holds(
            "backbone control with the leg reflexes climbs the highest step of all module sets",
            "beyond the paper: the modules of Fig. 10 ablated",
            (full or 0.0) >= best and (full or 0.0) > (none or 0.0),
            {name: x["highest_reliable_m"] for name, x in v.items()},
            f"highest step (m) climbed reliably ({s['rule']})",
        )
    ]


def real_robot(s: dict[str, Any]) -> list[Claim]:
    """Each event of the figure's ``real_robot`` entry: the median simulated time over the runs where it happened
    against the real robot's time (:func:`~neurowalk.experiments.reproduce.claims.timing`)."""
    rr = s["real_robot"]
    claims = []
    for name, e in rr["events"].items():
        sim = e["sim"]
        context = (
            f" at {rr['control_hz']:g} Hz, median over the {sim['happened']} of {sim['runs']} runs where it happened "
            f"(range {sim['min_s']}-{sim['max_s']} s)"
            if sim["happened"]
            else f" at {rr['control_hz']:g} Hz: in none of {sim['runs']} runs"
        )
        claims.append(timing(f"{name} (real robot: {e['paper']})", e["paper_s"], sim["median_s"], context))
    return claims


def fig8_real(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Fig. 8 at the real robot's rate: the outcomes and the escape time against 0:50."""
    return [*fig8(s, quick), *real_robot(s)]


def fig9_real(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Fig. 9 at the real robot's rate: the outcomes, the end of the path reached and the way out against 3:20."""
    return [*fig9(s, quick), *real_robot(s)]


def fig10_real(s: dict[str, Any], quick: bool) -> list[Claim]:
    """Fig. 10 at the real robot's rate: the track crossed, on the platforms against 0:23 and 1:14."""
    return [*fig10(s, quick), *real_robot(s)]
