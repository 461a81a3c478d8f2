"""The committed report says what its verdicts are made of: its top counts the claims as well as the results and
says how claims make a result's verdict; every measured value in its tables says its unit or what it counts."""

from __future__ import annotations

import json
import re
from pathlib import Path

from neurowalk.experiments.reproduce.report import _hinges, cell

RESULTS = Path(__file__).resolve().parents[3] / "docs" / "results"


def _claim_rows(text: str) -> list[list[str]]:
    """The cells of every claim row of the report's per-result tables."""
    rows, inside = [], False
    for line in text.splitlines():
        if line.startswith("| claim | paper | neurowalk |"):
            inside = True
            continue
        if inside and line.startswith("|---"):
            continue
        if inside and line.startswith("| "):
            rows.append([c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]])
        else:
            inside = False
    return rows


def test_the_top_counts_the_claims_and_says_how_they_make_a_verdict():
    for folder in (RESULTS, RESULTS / "quick"):
        top = (folder / "report.md").read_text(encoding="utf-8").split("\n\n")[1]
        totals = json.loads((folder / "reproduce.json").read_text())["claims"]
        records = [json.loads(p.read_text()) for p in folder.glob("*.json") if p.name != "reproduce.json"]
        every = [c for r in records for c in r["claims"]]
        assert totals == {
            "total": len(every),
            **{v: sum(c["verdict"] == v for c in every) for v in ("reproduced", "partly", "not")},
        }
        assert (f"Their {totals['total']} claims: {totals['reproduced']} reproduced, {totals['partly']} partly, "
                f"{totals['not']} not.") in top  # fmt: skip
        assert "reproduced where all of its claims are, not where all are not, and partly otherwise" in top


def test_every_measured_value_says_its_unit_or_what_it_counts():
    rows = _claim_rows((RESULTS / "report.md").read_text(encoding="utf-8"))
    assert len(rows) >= 60
    bare = [r for r in rows if re.fullmatch(r"[-+\d.,/e ]+", r[2])]  # numbers, counts, lists of them, and nothing
    assert not bare, f"measured values without a unit or a meaning: {[(r[0], r[2]) for r in bare]}"


def test_a_count_gets_its_meaning_and_a_word_stays_a_word():
    assert cell("10/10", "runs") == "10/10 runs" and cell("escaped", "runs") == "escaped"
    assert cell(0.35889, "(hysteresis width, input units)") == "0.359 (hysteresis width, input units)"
    assert cell("speed rises with |O|") == "speed rises with \\|O\\|"  # a table cell
    assert cell("speed rises with |O|", markdown=False) == "speed rises with |O|"  # the terminal


def test_a_result_names_the_invented_dimensions_its_claims_hinge_on():
    sens = {"claims": [
        {"what": "narrow passage: gap: plastic escaped",
         "paper": "escaped (Fig. 3B, 5B, 8)", "verdict": "partly"},
        {"what": "simple dead end: depth: static escaped",
         "paper": "escaped (Fig. 3A, 5A)", "verdict": "reproduced"},
    ]}  # fmt: skip
    records = {"sensitivity": sens}
    (line,) = [x for x in _hinges(records, "fig8-27hz") if x]
    assert "narrow passage: gap: plastic escaped hinges on it; 0 of 1 outcomes hold" in line and "depth" not in line
    assert "gap: plastic escaped hinges on it; 1 of 2 outcomes hold" in _hinges(records, "fig3")[1]
    assert _hinges(records, "fig10") == [] and _hinges(records, "table2") == [] and _hinges({}, "fig8") == []
