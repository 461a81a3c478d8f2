"""`neurowalk figure NAME` says its results against the paper where it makes them: the claims the reproduction
judges from the same command, one line each, and where the rules are."""

from __future__ import annotations

import json
from pathlib import Path

from neurowalk.cli import main
from neurowalk.experiments import FIGURES, Study
from neurowalk.experiments.command import claim_lines

RESULTS = Path(__file__).parents[1] / "docs" / "results"


def test_table2_says_its_rows_and_the_papers_counts_with_verdicts():
    summary = json.loads((RESULTS / "table2" / "table2.json").read_text())
    lines = claim_lines(FIGURES["table2"], summary, quick=False)
    assert lines[0] == "table2 against the paper:" and lines[-1].endswith("docs/results/details.md#table2)")
    rows = summary["counts"]
    assert lines[1] == "  successes: " + ", ".join(f"{k} {r['success']}/{r['environments']}" for k, r in rows.items())
    claims = json.loads((RESULTS / "table2.json").read_text())["claims"]  # the reproduction's, of the same numbers
    judged = lines[2:-1]
    assert len(judged) == len(claims) >= 2
    for line, c in zip(judged, claims, strict=True):
        assert line.startswith(f"  {c['what']}: paper ") and line.endswith(f" -> {c['verdict']}")
    assert f"neurowalk {rows['plastic-paper']['success']}/50 environments -> " in judged[0]


def test_the_terminal_shows_a_claim_as_written_not_as_a_table_cell(capsys, tmp_path):
    summary = json.loads((RESULTS / "table1" / "table1.json").read_text())
    lines = claim_lines(FIGURES["table1"], summary, quick=False)
    speed = next(line for line in lines if "walking speed" in line)
    assert "paper speed rises with |O|," in speed and "\\|" not in speed and " cm/s" in speed


def test_a_figure_prints_its_claims_after_its_files_and_not_with_other_settings(tmp_path, capsys):
    assert main(["figure", "fig2", "--quick", "--out", str(tmp_path / "a")]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("fig2: wrote") and out[1] == "fig2 against the paper (--quick: fewer, shorter runs):"
    assert all(" -> " in line for line in out[2:-1]) and len(out) > 3
    unjudged = Study("mine", "a study of no claims", plot=print, runs=lambda s: [], measure=lambda s, r: {})
    assert claim_lines(unjudged, {}, quick=False) == []
    assert main(["figure", "table1", "--quick", "--control-hz", "27", "--out", str(tmp_path / "b")]) == 0
    out = capsys.readouterr().out.splitlines()  # another command than the one judged: no verdicts
    assert len(out) == 1 and out[0].startswith("table1: wrote")
