"""Judges of the real-robot experiments run in simulation: Fig. 8 (narrow passage), Fig. 9 (complex path), Fig. 10
(climbing track), at the simulator's 10 Hz (outcomes) and at the real robot's 27 Hz (times), and the step sweep.

The paper's times are those of the real AMOSII, whose controller ran at about 27 Hz (§2.2); at 27 Hz the networks
take as many steps per second as on the real robot, so the times compare, up to the body and the floor.
"""

from __future__ import annotations

from typing import Any

import numpy as np

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


def _median(values: list[float | None]) -> float | None:
    """Median of the values that are not None (None where none is)."""
    got = sorted(v for v in values if v is not None)
    return None if not got else float(np.median(got))


def fig8_real(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The escape time of the plastic network against the real robot's 0:50 (at the real robot's rate)."""
    runs = s["counts"]["plastic"]["runs"]
    t = _median([r["exit_time_s"] for r in runs])
    return [
        *fig8(s, quick),
        timing("plastic network's escape time, median over seeds (Fig. 8: 0:50)", 50.0, t, _rate(s)),
    ]


def fig9_real(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The time the plastic network got out of the path against the real robot's 3:20."""
    runs = s["counts"]["plastic"]["runs"]
    t = _median([r["out_time_s"] for r in runs])
    return [
        *fig9(s, quick),
        timing("plastic network out of the path, median over seeds (Fig. 9: 3:20)", 200.0, t, _rate(s)),
    ]


def _rate(s: dict[str, Any]) -> str:
    """``" at 27 Hz"``: the control rate of the figure's runs, for a claim's rule."""
    return f" at {s.get('control_hz', 10.0):g} Hz"


def fig10_real(s: dict[str, Any], quick: bool) -> list[Claim]:
    """The example run's climbs against the real robot's times: on the first platform at 0:23, the second at
    1:14."""
    hz = s.get("control_hz", 10.0)
    m = s["moments"]
    first = None if m["first climb"] is None else m["first climb"] / hz
    second = None if m["second climb"] is None else m["second climb"] / hz
    return [
        *fig10(s, quick),
        timing("first step climbed (Fig. 10: on the first platform at 0:23)", 23.0, first, _rate(s)),
        timing("second step climbed (Fig. 10: on the second platform at 1:14)", 74.0, second, _rate(s)),
    ]
