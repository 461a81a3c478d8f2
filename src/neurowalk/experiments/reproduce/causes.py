"""Why a claim is not reproduced: one cause of :data:`KINDS` for every claim whose verdict is not ``reproduced``,
with the measurement that shows it, in one table (:data:`RULES`) beside the judges.

A cause is a statement with its evidence, read from the figure's own numbers (and, for Table 2's shortfall, from
the ablation study's record in the same folder). Where no rule of :data:`RULES` names a claim, or its evidence is
not there, the cause is ``unexplained``, said so: nothing is left without one.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

from neurowalk.experiments.reproduce.claims import Claim

KINDS: tuple[str, ...] = (
    "the paper's model as printed",
    "a neurowalk substitute",
    "invented geometry",
    "the simulated body against the real one",
    "unexplained",
)

Why = Callable[[dict[str, Any], Path], tuple[str, str] | None]


def _table2(summary: dict[str, Any], out: Path) -> tuple[str, str] | None:
    """The paper's reading's shortfall in Table 2: the ablation measures which of the code's options close it."""
    path = out / "ablation" / "ablation.json"
    if not path.is_file():
        return None
    s = json.loads(path.read_text(encoding="utf-8"))
    a, n = s["arms"], s["environments"]
    best = max(s["switched"], key=lambda o: a[f"paper + {o}"]["success"])
    f = a["paper"]["failure_classes_at_end"]
    return (
        "the paper's model as printed",
        f"in the ablation ({n} Table 2 environments, surrogate, {s['duration_s']:g} s), the paper's reading is not "
        f"stuck in {a['paper']['success']}, the code's in {a['original']['success']}, and the paper's reading with "
        f"every option of the code's in {a['paper + all']['success']}; the one option that adds most alone is "
        f"{best} ({a[f'paper + {best}']['success']}); the paper's reading fails mostly by latched spins "
        f"({f['latched spin']} of {sum(f.values())} failures at {s['lengths_s'][-1]:g} s)",
    )


def _fig9_map(summary: dict[str, Any], out: Path) -> tuple[str, str] | None:
    """fig9's plastic network out in some seeds only: the outcome map over the invented widths and spacings."""
    cells = summary.get("map") or []
    if not cells:
        return None
    words = ", ".join(
        f"{c['plastic']['got_out']}/{c['plastic']['seeds']} at width x{c['width_factor']:g} spacing "
        f"x{c['spacing_factor']:g}"
        for c in cells
    )
    return ("invented geometry", f"the outcome map over the path's invented width and spacing: {words}")


def _fig9_window(summary: dict[str, Any], out: Path) -> tuple[str, str] | None:
    """fig9-27hz's static network gets out: when it does, against the run's length."""
    runs = summary["counts"]["static"].get("runs", [])
    times = [r["out_time_s"] for r in runs if r.get("out_time_s") is not None]
    if not times:
        return None
    hz = summary["control_hz"]
    return (
        "a neurowalk substitute",
        f"the window: the static network leaves the path at {min(times):.0f}-{max(times):.0f} s "
        f"({round(min(times) * hz):,}-{round(max(times) * hz):,} control steps) of a {summary['duration_s']:g} s run "
        f"at {hz:g} Hz; the paper gives no window for its static robot (the rule's is the steps its plastic robot "
        "took to get out)",
    )


def _fig6(summary: dict[str, Any], out: Path) -> tuple[str, str] | None:
    """fig6's trap: how much of the bearing the invented environments block."""
    envs = summary.get("environments") or []
    blocked = [e["max_blocked_deg"] for e in envs if e.get("max_blocked_deg") is not None]
    if not blocked:
        return None
    return (
        "invented geometry",
        f"the {len(envs)} invented environments block {min(blocked):.0f}-{max(blocked):.0f} degrees of bearing "
        f"along the robot's path at most; the trap asks for {summary['class_numbers']['trap_blocked_deg']:g}, what the "
        "paper's own trap (the simple dead end) blocks measured the same way",
    )


def _interval(summary: dict[str, Any], out: Path) -> tuple[str, str] | None:
    """A real-robot interval: the simulated one against the paper's, with the body's speed on the same clock."""
    rr = summary.get("real_robot") or {}
    events = rr.get("events") or {}
    told = [
        f"{name} {e['sim']['median_s']:.0f} s (paper {e['paper_s']:g} s)"
        for name, e in events.items()
        if e["sim"]["median_s"] is not None
    ]
    if not told:
        return None
    return (
        "the simulated body against the real one",
        "the intervals start at an event the robot meets, not at the run's start: "
        + "; ".join(told)
        + f" at {rr['control_hz']:g} Hz. What is left is the body's speed and turning against the real robot's "
        "(the model walks about 1.5x and turns 1.3-1.5x as fast as the authors' simulated robot, "
        "docs/paper-vs-code.md) and the distances of an arena neurowalk invented (the sensitivity study)",
    )


def _sensitivity(summary: dict[str, Any], out: Path) -> tuple[str, str] | None:
    """The sensitivity study's cells where an outcome stops holding as the invented dimension is scaled."""
    off = []
    for case, c in summary.get("cases", {}).items():
        for net, paper in c["paper"].items():
            for cell in c["cells"]:
                k, n = cell[net]["as_paper"], cell[net]["runs"]
                if 3 * k < 2 * n:
                    off.append(f"{case}, {net} {paper}: {k}/{n} at x{cell['factor']:g} ({cell['value_m']:g} m)")
    if not off:
        return None
    return ("invented geometry", "the outcome holds at neurowalk's default and not at " + "; ".join(off))


#: (item, words its claim's ``what`` holds) -> the cause's measurement; the first rule that matches serves.
RULES: tuple[tuple[str, str, Why], ...] = (
    ("table2", "plastic-paper", _table2),
    ("table2-1000", "plastic-paper", _table2),
    ("table2-physics", "plastic-paper", _table2),
    ("fig9", "plastic network goes out", _fig9_map),
    ("fig9-27hz", "static network gets stuck", _fig9_window),
    ("fig9-27hz", "(real robot's photos)", _interval),
    ("fig8-27hz", "(real robot's photos)", _interval),
    ("fig10-27hz", "(real robot's photos)", _interval),
    ("fig6", "confined space and a trap", _fig6),
    ("sensitivity", ": ", _sensitivity),
)


def with_causes(item: str, claims: list[Claim], summary: dict[str, Any], out: Path) -> list[Claim]:
    """``claims`` with a ``cause`` ({"kind", "why"}) on each that is not reproduced (None on the others)."""
    done = []
    for c in claims:
        if c.verdict == "reproduced":
            done.append(replace(c, cause=None))
            continue
        rule = next((why for name, words, why in RULES if name == item and words in c.what), None)  # the first
        kind, text = (rule and rule(summary, out)) or ("unexplained", "no measurement names a cause yet")
        done.append(replace(c, cause={"kind": kind, "why": text}))
    return done
