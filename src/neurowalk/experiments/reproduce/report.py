"""``DIR/report.md``: every item of the plan in one table, paper against neurowalk (and, where it has runs of an item,
against the authors' own simulator: :mod:`.judge_authors`), then each item's results."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from typing import Any

from neurowalk.experiments.reproduce.judge_authors import SOURCE
from neurowalk.experiments.reproduce.plan import PLAN, settings_words
from neurowalk.fileio import atomic_write

DOCS = Path(__file__).resolve().parents[4] / "docs"  # the documentation, in a checkout
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


def cell(v: Any, unit: str = "", markdown: bool = True) -> str:
    """A value with its unit: numbers rounded, lists and dicts shortened; the unit after a number, a list, a dict or
    a text that holds a count (``10/10 runs``, ``plastic 24/30, static 10/30 runs``), not after a word (``escaped``).
    ``markdown``: for a table cell (pipes escaped), else for the terminal."""
    if isinstance(v, float):
        text = f"{v:.3g}"
    elif isinstance(v, dict):
        text = ", ".join(f"{k} {cell(x, markdown=False)}" for k, x in v.items())
    elif isinstance(v, list):
        text = ", ".join(cell(x, markdown=False) for x in v)
    else:
        text = "-" if v is None else str(v)
    counted = not isinstance(v, str) or re.search(r"\d+/\d+", v) is not None
    text = text + (f" {unit}" if unit and v is not None and counted else "")
    return text.replace("|", "\\|") if markdown else text


def _took(rec: dict[str, Any]) -> str:
    """A result's wall time, and where its command went on from a stopped one, that it is the last part's."""
    return f"{rec['wall_time_s']:.0f} s" + (" (resumed: its last part)" if rec.get("resumed") else "")


def _count(claims: list[dict[str, Any]]) -> str:
    """How many of ``claims`` (as in a record) are reproduced: "5 of 6"."""
    return f"{sum(c['verdict'] == 'reproduced' for c in claims)} of {len(claims)}"


def _authors_summary(rec: dict[str, Any]) -> str:
    """The authors' simulator's cell of the summary table: its claims reproduced, or that it is measured beside
    neurowalk only ("-" where it has no runs of the result)."""
    entry = rec.get("authors")
    if entry is None:
        return "-"
    return _count(entry["claims"]) if entry["claims"] else "side by side (no claim to judge)"


def _authors_claim(rec: dict[str, Any], what: str) -> str:
    """The authors' value and verdict of the claim ``what`` ("-" where their runs do not answer it)."""
    theirs = {c["what"]: c for c in (rec.get("authors") or {}).get("claims", [])}
    c = theirs.get(what)
    return "-" if c is None else f"{cell(c['measured'], c.get('unit', ''))} ({MARK[c['verdict']]})"


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
    """The report's markdown for the records in ``out`` (``failed``: item name -> why its run failed): one table
    of every result, then a section per result with its picture and its claims (their rules: :func:`render_details`)."""
    records, failed = read_records(out, quick), failed or {}
    counts = {v: sum(r["verdict"] == v for r in records.values()) for v in MARK}
    claims = claim_counts(records)
    lines = [
        "# The paper against neurowalk",
        "",
        f"{'Quick' if quick else 'Full'} reproduction: {len(records)} of {len(PLAN)} results measured: "
        f"{counts['reproduced']} reproduced, {counts['partly']} partly, {counts['not']} not"
        + (f"; {len(failed)} failed to run" if failed else "")
        + f". Their {claims['total']} claims: {claims['reproduced']} reproduced, {claims['partly']} partly, "
        f"{claims['not']} not. A result is reproduced where all of its claims are, not where all are not, and partly "
        "otherwise (a claim not reproduced among reproduced ones makes its result partly). "
        + f"{_made_on(records)} Each result's numbers: `NAME/NAME.json`, its claims: `NAME.json`, bit for bit on the "
        'same versions and CPU type (`docs/usage.md`, "Same seed, same result").',
        "",
        "Reproduced: two thirds or more of the seeds end as the paper's one run did; a count such as 49/50 passes "
        "Boschloo's exact test of the two counts at the 5% level (its p beside it); a real-robot time is within a "
        "factor of 1.5 (partly: some seeds, within 10 points, a factor of 3). A claim not reproduced names its cause; "
        "every rule, with its numbers, is in [the details](details.md). *Authors' simulator*: the same claims judged "
        "on runs of the authors' own simulator, where it has them (last section).",
        "",
        "| result | the paper | neurowalk: claims reproduced | authors' simulator | verdict | time |",
        "|---|---|---|---|---|---|",
    ]
    for item in PLAN:
        rec = records.get(item.name)
        if rec is None:
            why = f"failed: {failed[item.name]}" if item.name in failed else "not run"
            lines.append(f"| {item.name} | {cell(item.paper)} | {cell(why)} | - | - | - |")
            continue
        lines.append(
            f"| [{item.name}](#{item.name}) | {cell(item.paper)} | {_count(rec['claims'])} | {_authors_summary(rec)} "
            f"| {MARK[rec['verdict']]} | {_took(rec)} |"
        )
    for item, rec in _measured(records):
        lines += [
            "",
            f"## {item.name}",
            "",
            f"{item.paper}: **{rec['verdict']}**. {settings_words(rec['settings']).capitalize()} "
            f"(`{rec['command']}`; {_took(rec)}; "
            f"[details](details.md#{item.name}), [numbers]({rec['files']['json']})).",
            "",
            f"![{item.name}]({rec['files']['png']})",
            "",
        ]
        lines += _claims_table(rec)
        lines += _hinges(records, item.name)
    return "\n".join([*lines, *_provenance(out)]) + "\n"


def render_details(out: Path, quick: bool) -> str:
    """``DIR/details.md``, the report's second page: result by result, how each claim's verdict was reached (its
    rule, with the numbers it compared) and the numbers measured in both simulators, for the records in ``out``."""
    records = read_records(out, quick)
    lines = [
        "# The verdicts in detail",
        "",
        "Each claim of [the report](report.md) with the rule that gave its verdict and the numbers it compared; "
        "where the authors' simulator has runs of a result, the numbers measured in both simulators.",
    ]
    for item, rec in _measured(records):
        lines += ["", f"## {item.name}", "", f"{item.paper} ([in the report](report.md#{item.name})).", ""]
        lines += [f"- **{c['what']}** ({c['verdict']}): {c['rule']}.{_cause(c)}" for c in rec["claims"]]
        lines += _physics(out, rec)
        lines += _side_by_side(rec)
    return "\n".join(lines) + "\n"


def _measured(records: dict[str, dict[str, Any]]) -> list[tuple[Any, dict[str, Any]]]:
    """The items of the plan that ``records`` holds, in its order, each with its record."""
    return [(item, records[item.name]) for item in PLAN if item.name in records]


#: What the sensitivity study's verdict says of a claim's invented dimension, in words.
HINGE = {"reproduced": "holds", "partly": "hinges on it", "not": "fails at the default"}


def _hinges(records: dict[str, dict[str, Any]], name: str) -> list[str]:
    """A line under result ``name`` (a paper figure ``figN``) on the sensitivity study's claims on its arena (the
    claim's ``paper`` names the figures): those that do not hold with the invented dimension at 0.8-1.2 x, and how
    many do; none where the study has none or did not run."""
    fig = re.match(r"fig(\d+)", name)
    sens = records.get("sensitivity")
    if fig is None or sens is None:
        return []
    mine = [c for c in sens["claims"] if fig.group(1) in re.findall(r"(\d+)[A-Z]?", c["paper"].rpartition("(")[2])]
    if not mine:
        return []
    off = [f"{c['what']} {HINGE[c['verdict']]}" for c in mine if c["verdict"] != "reproduced"]
    held = len(mine) - len(off)
    words = "; ".join([*off, f"{held} of {len(mine)} outcomes hold"])
    return ["", f"Invented geometry at 0.8-1.2 x ([sensitivity](#sensitivity)): {words}."]


def _cause(c: dict[str, Any], words: str = " Cause: *{kind}*: {why}.") -> str:
    """``words`` with a claim's cause (its ``kind`` and ``why``) for a claim not reproduced, else ""; the table's:
    `` (cause: KIND)``."""
    cause = c.get("cause")
    return "" if not cause else words.format(kind=cause["kind"], why=cause["why"])


def _physics(out: Path, rec: dict[str, Any]) -> list[str]:
    """The physics the result's runs stepped (its json's ``physics_settings``), a line each; none for a result
    without physics runs."""
    path = Path(out) / rec["files"]["json"]
    physics = json.loads(path.read_text()).get("physics_settings", []) if path.is_file() else []
    return [
        f"- Physics of its `{p['body']}` runs at `{p['control_hz']:g} Hz`: `{p['substeps']}` steps of "
        f"`{p['timestep_s'] * 1000:.4g} ms` a control step, `{p['integrator']}`, `{p['solver']}` to "
        f"`{p['tolerance']:g}` (at most `{p['iterations']}` iterations), the `{p['cone']}` friction cone."
        for p in physics
    ]


def _claims_table(rec: dict[str, Any]) -> list[str]:
    """A result's claims as a table: claim, paper, neurowalk, verdict, and the 95% interval and the authors'
    simulator's columns only where some claim has one (an empty column is left out, not filled with dashes)."""
    claims = rec["claims"]
    intervals = any(c["interval"] is not None for c in claims)
    theirs = any(_authors_claim(rec, c["what"]) != "-" for c in claims)
    head = ["claim", "paper", "neurowalk", *(["95% interval"] if intervals else []), "verdict"]
    head += ["authors' simulator"] if theirs else []
    rows = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for c in claims:
        row = [cell(c["what"]), cell(c["paper"], c["unit"]), cell(c["measured"], c["unit"])]
        row += [_interval(c)] if intervals else []
        row += [f"{MARK[c['verdict']]}{_cause(c, ' (cause: {kind})')}"]
        row += [_authors_claim(rec, c["what"])] if theirs else []
        rows.append("| " + " | ".join(row) + " |")
    return rows


def _interval(c: dict[str, Any]) -> str:
    """A claim's 95% interval as percentages ("-" where it has none) and, for a count, its test's p ("; p 0.54"; the
    shortfall the samples could show is in the details)."""
    if c["interval"] is None:
        return "-"
    words = f"{c['interval'][0]:.0%}-{c['interval'][1]:.0%}"
    test = c.get("test")
    if test:
        words += f"; p {test['p_value']:.2g}"
    return words


def _made_on(records: dict[str, dict[str, Any]]) -> str:
    """The versions and machine of the records, said once where they share them."""
    keys = ("neurowalk", "mujoco", "numpy", "numba", "matplotlib", "python", "machine")
    made = {tuple(r["versions"].get(k, "?") for k in keys) for r in records.values()}
    if len(made) != 1:
        return "The versions and machine of each result are in its `NAME.json`."
    nw, mj, np_, nb, mpl, py, machine = made.pop()
    cpus: dict[str, list[str]] = {}
    for name, r in records.items():
        cpus.setdefault(r["versions"].get("cpu", "?").split(",")[0].removeprefix("numba_cpu "), []).append(name)
    where = (
        f"CPU {next(iter(cpus))}"
        if len(cpus) == 1
        else "CPUs " + "; ".join(f"{cpu} ({', '.join(names) if len(names) < 5 else f'{len(names)} results'})"
                                 for cpu, names in sorted(cpus.items(), key=lambda kv: -len(kv[1])))
    )  # fmt: skip
    return (
        f"Made with neurowalk {nw}, MuJoCo {mj}, numpy {np_}, numba {nb}, matplotlib {mpl} and Python {py} on "
        f"{machine}, {where} (every version: `requirements.lock`)."
    )


def _docs_link(out: Path, page: str, words: str) -> str:
    """``words`` linked to the documentation's ``page`` from a report in ``out`` (where the docs are beside the
    package, as in a checkout), else with the page's path."""
    target = DOCS / page
    if not target.is_file():
        return f"{words} (`docs/{page}`)"
    return f"[{words}]({Path(os.path.relpath(target, Path(out).resolve())).as_posix()})"


def _provenance(out: Path) -> list[str]:
    """The closing section: where the authors' simulator's runs come from."""
    page = _docs_link(out, "authors-simulator.md", "The authors' simulator")
    return [
        "",
        "## The authors' simulator",
        "",
        f"The second reference is {SOURCE}. Their trajectories were measured here with neurowalk's own "
        "metrics (escape, trapping, wedged periods, coverage; the trunk centre 0.06 m ahead of the logged rear "
        "trunk box) and judged by each claim's own rule; each result's `NAME.json` holds them under `authors`. "
        f"{page} says where the data come from and compares the two simulators.",
    ]


def claim_counts(records: dict[str, dict[str, Any]]) -> dict[str, int]:
    """The claims of the results ``records`` hold, in all and by verdict."""
    every = [c for r in records.values() for c in r["claims"]]
    return {"total": len(every), **{v: sum(c["verdict"] == v for c in every) for v in MARK}}


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
        "claims": claim_counts(records),
        "not_reproduced": [
            {"result": name, "what": c["what"], "verdict": c["verdict"], "cause": c.get("cause")}
            for name, r in records.items()
            for c in r["claims"]
            if c["verdict"] != "reproduced"
        ],
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
    """Write ``DIR/report.md``, ``DIR/details.md`` (:func:`render_details`) and ``DIR/reproduce.json`` (:func:`totals`),
    each atomically, from the records in ``out``; the report's path."""
    _write_text(out / "report.md", render(out, quick, failed))
    _write_text(out / "details.md", render_details(out, quick))
    _write_text(out / "reproduce.json", json.dumps(totals(out, quick), indent=2) + "\n")
    return out / "report.md"


def _write_text(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` (UTF-8), whole or not at all."""
    atomic_write(path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
