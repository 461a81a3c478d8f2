"""The authors' simulator beside neurowalk: each comparable claim of an item judged on the authors' runs by the rule
the claim uses (:mod:`.claims`), and the numbers both give side by side.

:func:`compare` gives an item record's ``"authors"`` entry (None for an item the data has no run for):

* ``claims``: one per claim of the item that the authors' runs answer, matched by the claim's ``what``:
  ``what``, ``measured`` (the authors' value), ``verdict`` and ``rule`` as :class:`~.claims.Claim` has them;
* ``side_by_side``: numbers without a claim of their own (Table 1's speeds, the CPG period, the long runs):
  ``what``, ``unit``, ``authors``, ``neurowalk``;
* ``reason``: the authors' system against the paper in a line ("reproduced (3/3)").

Nothing here changes neurowalk's own verdicts (:func:`~.claims.overall` of the item's claims).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from neurowalk import metrics
from neurowalk.experiments.figures import table1
from neurowalk.experiments.reproduce import authors
from neurowalk.experiments.reproduce.claims import Claim, holds, outcome

#: Where the runs come from, in a line (the package data's README.md says it in full).
SOURCE = (
    "the authors' simulator: LPZRobots 94d406a (ODE 0.11.1) with the authors' AMOSII controller (gorobots_edu "
    "a2cadfe), 0.01 s physics step, 10 Hz control, sensor noise 0.02"
)
DATA = "neurowalk/experiments/reproduce/authors_simulator/"  # where their runs are, in the package
#: A claim's authors' counterpart: ``(claim, summary) -> Claim`` on the authors' runs.
Rule = Callable[[Claim, dict[str, Any]], Claim]


def _dead_end(arena: str, network: str, want: str) -> Rule:
    """The outcome rule over the authors' seeds 10-12 (the further seeds' count in the rule, where run)."""

    def rule(c: Claim, s: dict[str, Any]) -> Claim:
        cell = authors.dead_ends()[arena][network]
        got = outcome(c.what, c.paper, cell[want], cell["runs"])
        exits = ", ".join(f"{x:.0f}" for x in cell["exit_s"]) or "none"
        more = cell.get("more")
        extra = f"; seeds {more['seed_list'][0]}-{more['seed_list'][-1]}: {more[want]}/{more['runs']}" if more else ""
        return Claim(c.what, c.paper, got.measured, got.verdict, f"{got.rule}; exit times (s): {exits}{extra}")

    return rule


def _static_trapped(c: Claim, s: dict[str, Any]) -> Claim:
    r = authors.long_runs()["static"]
    return holds(
        c.what,
        c.paper,
        r["trapped"],
        f"coverage {r['coverage']:.1%}",
        f"one run of {r['steps']} control steps; longest wedged period {r['longest_wedged_s']:.0f} s, longest held "
        f"{r['longest_held_s']:.0f} s",
    )


def _plastic_explores(c: Claim, s: dict[str, Any]) -> Claim:
    p, st = authors.long_runs()["plastic"], authors.long_runs()["static"]
    return holds(
        c.what,
        c.paper,
        not p["trapped"] and p["coverage"] > st["coverage"],
        f"coverage {p['coverage']:.1%} (static {st['coverage']:.1%}), {'stuck' if p['trapped'] else 'not stuck'}",
        f"one run of {p['steps']} control steps: not stuck at the end and more of the free area visited than the "
        "static network's run in the same arena",
    )


def _plastic_not_held(c: Claim, s: dict[str, Any]) -> Claim:
    p = authors.long_runs()["plastic"]
    return holds(
        c.what,
        c.paper,
        p["held_over_300s"] == 0,
        f"{p['held_over_300s']} held over 300 s; {p['wedged_periods']} wedged periods, of which "
        f"{p['turning_periods']} turning; longest wedged {p['longest_wedged_s']:.0f} s",
        f"held: trunk centre within {metrics.WEDGE_RADIUS:g} m and heading within {metrics.HELD_HEADING_DEG:g} "
        f"degrees for more than {metrics.WEDGE_MIN_S:g} s (neurowalk's metrics.wedged_periods on the authors' path); "
        f"turning: wedged with the heading sweeping more; causes of the wedged periods: {p['wedged_causes'] or '-'}",
    )


def _direction(case: str) -> Rule:
    """Table 1's rule for the flat-ground run ``case``: the measured direction is the paper's."""

    def rule(c: Claim, s: dict[str, Any]) -> Claim:
        r = authors.flat_ground()[case]
        lo, hi = authors.TABLE1_WINDOW_S
        return holds(
            c.what,
            c.paper,
            r["direction"] == r["paper"],
            r["direction"],
            f"{100 * r['speed_m_per_s']:.2f} cm/s along the start heading, {r['turn_rate_deg_per_s']:.2f} deg/s "
            f"turning (positive left) over t = {lo:g}-{hi:g} s, {table1.DIRECTION_RULE}",
        )

    return rule


#: Per item: the start of each comparable claim's ``what`` and its rule on the authors' runs.
RULES: dict[str, dict[str, Rule]] = {
    "table1": {f"outputs ({o1:+d}, {o2:+d}) walk": _direction(case) for case, (o1, o2) in authors.FLAT_GROUND.items()},
    "fig3": {
        "static network escapes the simple dead end": _dead_end("simple-deadlock", "static", "escaped"),
        "static network is trapped in the narrow passage": _dead_end("narrow-passage", "static", "trapped"),
        "static network is trapped in the difficult arena": _static_trapped,
    },
    "fig5": {
        "plastic network escapes the simple dead end": _dead_end("simple-deadlock", "plastic", "escaped"),
        "plastic network escapes the narrow passage": _dead_end("narrow-passage", "plastic", "escaped"),
        "plastic network explores the difficult arena: not stuck at the end": _plastic_explores,
        "no held period over 300 s": _plastic_not_held,
    },
    "fig7": {},
}


def _row(what: str, unit: str, ours: Any, theirs: Any, digits: int = 4) -> dict[str, Any]:
    """A side-by-side row; numbers rounded to ``digits`` decimals (None: not measured)."""

    def r(v: Any) -> Any:
        return round(float(v), digits) if isinstance(v, float) else v

    return {"what": what, "unit": unit, "authors": r(theirs), "neurowalk": r(ours)}


def _table1_rows(s: dict[str, Any]) -> list[dict[str, Any]]:
    """Speed (cm/s) and turning rate (deg/s) of each flat-ground case, neurowalk's from the figure's ``signs``."""
    ours = {(r["O1"], r["O2"]): r for r in s["signs"]}
    rows = []
    for case, r in authors.flat_ground().items():
        n = ours.get((r["O1"], r["O2"]), {})
        speed = n.get("speed_m_per_s")
        rows.append(_row(f"{case}: speed", "cm/s", None if speed is None else 100 * speed, 100 * r["speed_m_per_s"]))
        rows.append(_row(f"{case}: turning rate", "deg/s", n.get("turn_rate_deg_per_s"), r["turn_rate_deg_per_s"]))
    return rows


def _fig7_rows(s: dict[str, Any]) -> list[dict[str, Any]]:
    """The gait period in control steps: the authors' CPG output against neurowalk's hind CTr joint (fig7)."""
    ours = s["conditions"]["forward"]["period_s"] * s["control_hz"]
    what = "CPG period, walking forward (authors: the CPG output; neurowalk: a hind leg's CTr joint)"
    return [_row(what, "steps", ours, authors.cpg_period(), 2)]


def _long_rows(s: dict[str, Any], network: str) -> list[dict[str, Any]]:
    """The long run of ``network`` in the difficult arena: length, coverage, wedged periods, stuck at the end."""
    r = authors.long_runs()[network]
    ours, w = s["runs"][f"difficult ({network})"], s["wedged"][f"difficult ({network})"]
    over = next(v for k, v in w.items() if k.startswith("over_"))
    held = w["held"]
    held_over = next(v["periods"] for k, v in held.items() if k.startswith("over_"))
    rows = [  # (what, unit, neurowalk's, the authors', digits)
        ("run length", "s", ours["steps"] / s["control_hz"], r["seconds"], 1),
        ("coverage", "share", ours["coverage"], r["coverage"], 4),
        ("wedged periods", "", w["periods"], r["wedged_periods"], 4),
        ("longest wedged period", "s", w["longest_s"], r["longest_wedged_s"], 1),
        ("wedged periods over 300 s", "", over["periods"], r["over_300s"], 4),
        ("held periods over 300 s", "", held_over, r["held_over_300s"], 4),
        ("longest held period", "s", held["longest_s"], r["longest_held_s"], 1),
        ("turning periods (wedged, never held)", "", held["turning_periods"], r["turning_periods"], 4),
        ("stuck at the end", "", bool(ours["trapped"]), r["trapped"], 4),
    ]
    return [_row(f"difficult arena, {network}: {what}", *rest) for what, *rest in rows]


def _static_simple_rows(s: dict[str, Any]) -> list[dict[str, Any]]:
    """The static network in the simple dead end, where the two simulators differ: escapes over all seeds, exit
    times, the longer runs, and where the runs not out in 500 s stay (end position, heading range at the end)."""
    cell, ours = authors.dead_ends()["simple-deadlock"]["static"], s["table"]["counts"]["simple-deadlock"]["static"]
    example = s["runs"]["simple-deadlock"]
    more, long = cell["more"], cell["long"]
    stay = [r for r in cell["seeds"] if not r["escaped"]]
    end = np.median([r["end"] for r in stay], axis=0) if stay else None
    first = s["table"]["first_seed"]
    what = "simple dead end, static"
    ex = (
        None
        if example["exit_step"] is None
        else f"{example['exit_step'] / s['control_hz']:.0f} (seed {example['seed']})"
    )
    return [
        _row(
            f"{what}: escaped in 500 s (authors: seeds {more['seed_list'][0]}-{more['seed_list'][-1]}; neurowalk: "
            + (f"seeds {first}-{first + ours['runs'] - 1})" if ours["runs"] > 1 else f"seed {first})"),
            "",
            f"{ours['escaped']}/{ours['runs']}",
            f"{more['escaped']}/{more['runs']}",
        ),
        _row(f"{what}: exit times (s)", "", ex, ", ".join(f"{x:.0f}" for x in more["exit_s"]) or None),
        _row(
            f"{what}: escaped in 1,500 s (seeds {', '.join(str(r['seed']) for r in long)})",
            "",
            None,
            f"{sum(r['escaped'] for r in long)}/{len(long)}"
            + "".join(f", seed {r['seed']} at {r['exit_s']:,.0f} s" for r in long if r["escaped"]),
        ),
        _row(
            f"{what}: runs still in at 500 s, median end position (x, y; m)",
            "",
            None,
            None if end is None else f"{end[0]:.2f}, {end[1]:.2f}",
        ),
        _row(
            f"{what}: runs still in at 500 s, median range of the heading over the last 300 s",
            "deg",
            None,
            float(np.median([r["end_heading_range_deg"] for r in stay])) if stay else None,
            1,
        ),
    ]


#: Per item: its side-by-side rows from the figure's summary.
ROWS: dict[str, Callable[[dict[str, Any]], list[dict[str, Any]]]] = {
    "table1": _table1_rows,
    "fig3": lambda s: [*_static_simple_rows(s), *_long_rows(s, "static")],
    "fig5": lambda s: [*_long_rows(s, "plastic"), *_long_rows(s, "static")[1:2]],
    "fig7": _fig7_rows,
}


def reason(claims: list[Claim]) -> str:
    """The authors' system against the paper in a line: ``reproduced (3/3)``, ``partly (2/3; not: WHAT: VALUE)``,
    ``not (0/2)``; ``side by side only`` where no claim compares."""
    if not claims:
        return "side by side only (no claim of the paper to judge)"
    ok = sum(c.verdict == "reproduced" for c in claims)
    word = "reproduced" if ok == len(claims) else "not" if all(c.verdict == "not" for c in claims) else "partly"
    off = "; ".join(f"{c.verdict}: {c.what}: {c.measured}" for c in claims if c.verdict != "reproduced")
    return f"{word} ({ok}/{len(claims)}{'; ' + off if off and word == 'partly' else ''})"


def compare(item: str, summary: dict[str, Any], claims: list[Claim]) -> dict[str, Any] | None:
    """The ``"authors"`` entry of item ``item``'s record from the figure's ``summary`` and neurowalk's ``claims``
    (see the module doc); None where the authors' runs answer nothing of the item."""
    if item not in RULES:
        return None
    theirs, used = [], set()
    for c in claims:
        start = next((start for start in RULES[item] if c.what.startswith(start)), None)
        if start is not None:
            theirs.append(RULES[item][start](c, summary))
            used.add(start)
    lost = [start for start in RULES[item] if start not in used]
    if lost:  # a claim reworded: its comparison with the authors' runs would drop out unseen
        raise ValueError(f"the authors' rule {lost[0]!r} of {item} matches none of its claims (reworded?)")
    keep = ("what", "measured", "verdict", "rule")
    return {
        "source": f"{SOURCE}; data in {DATA}",
        "claims": [{k: v for k, v in c.to_json().items() if k in keep} for c in theirs],
        "side_by_side": ROWS[item](summary),
        "reason": f"the authors' simulator: {reason(theirs)}",
    }
