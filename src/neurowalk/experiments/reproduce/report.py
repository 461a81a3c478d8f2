"""``DIR/report.md``: every item of the plan in one table, paper against neurowalk (and, where it has runs of an item,
against the authors' own simulator: :mod:`.judge_authors`), then each item's results."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from neurowalk.experiments.reproduce.judge_authors import SOURCE
from neurowalk.experiments.reproduce.plan import PLAN
from neurowalk.fileio import atomic_write

MARK = {"reproduced": "reproduced", "partly": "partly", "not": "**not**"}


def read_records(out: Path, quick: bool) -> dict[str, dict[str, Any]]:
    """The item records (``DIR/NAME.json``) in ``out`` made in the same mode (quick or full), by item name."""
    records = {}
    for item in PLAN:
        try:
            rec = json.loads((out / f"{item.name}.json").read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if isinstance(rec, dict) and rec.get("quick") == quick and rec.get("name") == item.name:
            records[item.name] = rec
    return records


def cell(v: Any, unit: str = "") -> str:
    """A value for a table cell: numbers rounded, lists and dicts shortened, pipes escaped."""
    if isinstance(v, float):
        text = f"{v:.3g}"
    elif isinstance(v, dict):
        text = ", ".join(f"{k} {cell(x)}" for k, x in v.items())
    elif isinstance(v, list):
        text = ", ".join(cell(x) for x in v)
    else:
        text = "-" if v is None else str(v)
    text = text + (f" {unit}" if unit and v is not None and not isinstance(v, str) else "")
    return text.replace("|", "\\|")


def _took(rec: dict[str, Any]) -> str:
    """A result's wall time, and where its command went on from a stopped one, that it is the last part's."""
    return f"{rec['wall_time_s']:.0f} s" + (" (resumed: its last part)" if rec.get("resumed") else "")


def _authors_reason(rec: dict[str, Any]) -> str:
    """The authors' simulator's line of a record for the table of all items ("-" where it has no runs of it)."""
    entry = rec.get("authors")
    return "-" if entry is None else cell(entry["reason"].removeprefix("the authors' simulator: "))


def _authors_claim(rec: dict[str, Any], what: str) -> str:
    """The authors' value and verdict of the claim ``what`` ("-" where their runs do not answer it)."""
    theirs = {c["what"]: c for c in (rec.get("authors") or {}).get("claims", [])}
    c = theirs.get(what)
    return "-" if c is None else f"{cell(c['measured'])} ({MARK[c['verdict']]})"


def _side(v: Any, unit: str) -> str:
    """A side-by-side value: a share as a percentage, yes / no, a number with its unit."""
    if isinstance(v, bool):
        return "yes" if v else "no"
    if unit == "share" and isinstance(v, float):
        return f"{100 * v:.1f}%"
    if isinstance(v, float):
        return (f"{v:,.0f}" if abs(v) >= 100 else f"{v:.3g}") + (f" {unit}" if unit else "")
    return cell(v, unit)


def _side_by_side(rec: dict[str, Any]) -> list[str]:
    """The table of numbers measured in both simulators without a claim of their own (none: no lines)."""
    rows = (rec.get("authors") or {}).get("side_by_side", [])
    if not rows:
        return []
    lines = ["", "Measured in both simulators:", "", "| measure | neurowalk | authors' simulator |", "|---|---|---|"]
    for r in rows:
        lines.append(f"| {cell(r['what'])} | {_side(r['neurowalk'], r['unit'])} | {_side(r['authors'], r['unit'])} |")
    return lines


def render(out: Path, quick: bool, failed: dict[str, str] | None = None) -> str:
    """The report's markdown for the records in ``out`` (``failed``: item name -> why its run failed)."""
    records, failed = read_records(out, quick), failed or {}
    counts = {v: sum(r["verdict"] == v for r in records.values()) for v in MARK}
    lines = [
        "# neurowalk reproduce: the paper against neurowalk",
        "",
        f"{'Quick' if quick else 'Full'} reproduction: {len(records)} of {len(PLAN)} results measured; "
        f"{counts['reproduced']} reproduced, {counts['partly']} partly, {counts['not']} not"
        + (f"; {len(failed)} failed to run" if failed else "")
        + ". Each result's file `NAME.json` holds the command, versions, seeds, wall time, the measured values "
        "with 95% intervals where they are rates, the paper's values and the rule of each verdict. The same "
        "commands give these numbers bit for bit on the same versions and CPU type; on another CPU a few of them "
        'may differ in their last bits, and no verdict or count does (measured: `docs/usage.md`, "Same seed, same '
        'result").',
        "",
        "How a verdict is reached (each claim states its own rule and numbers): an outcome the paper shows in one "
        "run is reproduced where two thirds or more of the seeds end that way, partly where some do; a count such "
        "as 49/50 is reproduced where the paper's rate lies in the measured 95% interval, partly within 10 points; a "
        "time of the real robot is reproduced within a factor of 1.5, partly within 3; a property stated in words "
        "is reproduced where it holds. A result is reproduced where all its claims are, not where all are not, and "
        "partly otherwise; its reason counts the claims reproduced and names the others under their verdicts.",
        "",
        "A second reference: the column *authors' simulator* judges the same claims, by the same rules, on runs of "
        "the authors' own simulator (LPZRobots with their controller; the last section says where they come from), "
        "where it has runs of them: Table 1, Fig. 3 and 5 (the dead ends with seeds 10-12, the difficult arena for "
        "10,000 s), and the CPG period beside Fig. 7. It says whether their system reproduces the paper; the verdict "
        "column is neurowalk's alone.",
        "",
        "| result | the paper | verdict | why | authors' simulator | figure | time |",
        "|---|---|---|---|---|---|---|",
    ]
    for item in PLAN:
        rec = records.get(item.name)
        if rec is None:
            why = f"failed: {failed[item.name]}" if item.name in failed else "not run"
            lines.append(f"| {item.name} | {cell(item.paper)} | - | {cell(why)} | - | - | - |")
            continue
        png = f"[{rec['figure']}.png]({rec['files']['png']})"
        lines.append(
            f"| [{item.name}](#{item.name}) | {cell(item.paper)} | {MARK[rec['verdict']]} | {cell(rec['reason'])} "
            f"| {_authors_reason(rec)} | {png} | {_took(rec)} |"
        )
    for item in PLAN:
        rec = records.get(item.name)
        if rec is None:
            continue
        lines += [
            "",
            f"## {item.name}",
            "",
            f"{item.paper}. Command: `{rec['command']}` ({_took(rec)}; control rate "
            f"{rec['control_hz']:g} Hz; neurowalk {rec['versions']['neurowalk']}, MuJoCo {rec['versions']['mujoco']}; "
            f"{rec['versions']['machine']}).",
            "",
            f"![{item.name}]({rec['files']['png']})",
            "",
            "| result | paper | neurowalk | 95% interval | verdict | rule | authors' simulator |",
            "|---|---|---|---|---|---|---|",
        ]
        for c in rec["claims"]:
            ci = "-" if c["interval"] is None else f"{c['interval'][0]:.0%}-{c['interval'][1]:.0%}"
            lines.append(
                f"| {cell(c['what'])} | {cell(c['paper'], c['unit'])} | {cell(c['measured'], c['unit'])} | {ci} "
                f"| {MARK[c['verdict']]} | {cell(c['rule'])} | {_authors_claim(rec, c['what'])} |"
            )
        lines += _side_by_side(rec)
    return "\n".join([*lines, *_provenance()]) + "\n"


def _provenance() -> list[str]:
    """The closing section: where the authors' simulator's runs come from."""
    return [
        "",
        "## The authors' simulator",
        "",
        f"The second reference is {SOURCE}. Their trajectories were measured here with neurowalk's own metrics "
        "(escape, trapping, wedged periods, coverage; the trunk centre 0.06 m ahead of the logged rear trunk box) "
        "and judged by each claim's own rule; each result's file `NAME.json` holds them under `authors`. The "
        "data's README.md (in that folder) gives the build, the settings and the trimming; `docs/authors-simulator.md` "
        "compares the two simulators.",
    ]


def totals(out: Path, quick: bool) -> dict[str, Any]:
    """The whole reproduction in numbers (``DIR/reproduce.json``): how many results were measured and with which
    verdicts, and the wall time of its distinct figure commands (``DIR/*/command.json``; a command stopped and
    resumed counts its last part only), on which machine."""
    records = read_records(out, quick)
    commands = [json.loads(p.read_text(encoding="utf-8")) for p in sorted(out.glob("*/command.json"))]
    return {
        "quick": quick,
        "results": len(PLAN),
        "measured": len(records),
        "verdicts": {v: sum(r["verdict"] == v for r in records.values()) for v in MARK},
        "commands": len(commands),
        "wall_time_s": round(sum(c["wall_time_s"] for c in commands), 1),
        "resumed_commands": sum(bool(c.get("resumed")) for c in commands),
        "machine": commands[0]["versions"]["machine"] if commands else None,
        "profile": profile_totals(out),
    }


def profile_totals(out: Path) -> dict[str, Any]:
    """Where the time of the figure commands went (:mod:`neurowalk.profiling`): per command (``DIR/RUN``) its wall
    time, the seconds of each part summed over its processes and its physics steps per second; and all of them
    added up."""
    per: dict[str, Any] = {}
    for path in sorted(out.glob("*/command.json")):
        rec = json.loads(path.read_text(encoding="utf-8"))
        if rec.get("profile") is not None:
            per[path.parent.name] = rec["profile"]
    seconds: dict[str, float] = {}
    for p in per.values():
        for k, v in p["seconds"].items():
            seconds[k] = round(seconds.get(k, 0.0) + v, 1)
    steps = sum(p["physics_steps"] for p in per.values())
    return {
        "seconds": seconds,
        "physics_steps": steps,
        "physics_steps_per_s": round(steps / seconds["physics"]) if seconds.get("physics") else None,
        "per_command": per,
    }


def write_report(out: Path, quick: bool, failed: dict[str, str] | None = None) -> Path:
    """Write ``DIR/report.md`` and ``DIR/reproduce.json`` (:func:`totals`), each atomically, from the records in
    ``out``; the report's path."""
    path = out / "report.md"
    text = render(out, quick, failed)
    atomic_write(path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
    summary = json.dumps(totals(out, quick), indent=2) + "\n"
    atomic_write(out / "reproduce.json", lambda tmp: Path(tmp).write_text(summary, encoding="utf-8"))
    return path
