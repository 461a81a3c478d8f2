"""The committed reproduction (docs/results/) and the current code agree: its report is what its records render,
every record is what the current claims judge from its numbers, and the times `figure list` shows are the committed
runs' times. (How long the runs took is a benchmark's: benchmarks/reproduction_times.py, not a test's.)"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from neurowalk.experiments.reproduce.gallery import REPLAYS, gallery
from neurowalk.experiments.reproduce.plan import PLAN
from neurowalk.experiments.reproduce.report import render, render_details, totals
from neurowalk.experiments.reproduce.runner import rejudged
from neurowalk.experiments.reproduce.timing import TIMES, measured_times

RESULTS = Path(__file__).parents[3] / "docs" / "results"
QUICK = RESULTS / "quick"


def test_the_quick_reproduction_has_a_verdict_for_every_result_and_its_report():
    for item in PLAN:
        rec = json.loads((QUICK / f"{item.name}.json").read_text())
        # judged: its claims and verdicts are the judges' now (test_every_committed_record_is_what_the_judges_say_now)
        assert rec["quick"] is True and rec["claims"], item.name
        assert (QUICK / rec["files"]["json"]).is_file(), item.name  # the numbers it was judged from
    assert (QUICK / "report.md").read_text() == render(QUICK, quick=True)
    assert (QUICK / "details.md").read_text() == render_details(QUICK, quick=True)


def test_the_quick_reproductions_totals_are_what_its_records_sum_to():
    assert json.loads((QUICK / "reproduce.json").read_text()) == totals(QUICK, quick=True)


def test_the_full_reproduction_has_a_record_for_every_result_and_its_report():
    """`neurowalk reproduce` (full) ran and is committed: every result, its numbers, its picture, its report."""
    for item in PLAN:
        rec = json.loads((RESULTS / f"{item.name}.json").read_text())
        assert rec["quick"] is False and rec["claims"], item.name  # judged, as the quick records
        assert not rec["settings"].get("quick") and rec["settings"] == item.given(quick=False), item.name
        assert (RESULTS / rec["files"]["json"]).is_file() and (RESULTS / rec["files"]["png"]).is_file(), item.name
    assert (RESULTS / "report.md").read_text() == render(RESULTS, quick=False)
    assert (RESULTS / "details.md").read_text() == render_details(RESULTS, quick=False)
    summary = json.loads((RESULTS / "reproduce.json").read_text())
    assert summary == totals(RESULTS, quick=False) and summary["measured"] == len(PLAN)


def test_the_gallery_shows_every_figure_of_the_full_run():
    page = RESULTS.parent / "gallery.md"
    assert page.read_text() == gallery(RESULTS, page)
    for item in PLAN:
        assert f"](results/{item.name}/" in page.read_text(), item.name


def test_figure_times_are_the_committed_runs():
    assert json.loads(TIMES.read_text()) == measured_times(RESULTS, QUICK)


def test_every_committed_record_is_what_the_judges_say_now():
    """A changed judge (or verdict wording) is carried into the committed records: each record's claims, verdict
    and reason are those the current code gives from the run's committed numbers."""
    for out in (RESULTS, QUICK):
        for item in PLAN:
            rec = json.loads((out / f"{item.name}.json").read_text())
            assert rejudged(item, rec, out) == rec, (out.name, item.name)


def test_the_gallery_embeds_its_replays():
    """The two runs the gallery embeds: committed, each one self-contained HTML file small enough to send."""
    page = (RESULTS.parent / "gallery.md").read_text()
    for name in REPLAYS:
        path = RESULTS.parent / "replays" / f"{name}.html"
        head = path.read_text(encoding="utf-8")[:200].lower()
        assert head.lstrip().startswith("<!doctype html") and path.stat().st_size < 5e6, name
        assert f'src="../replays/{name}.html"' in page, name


@pytest.mark.parametrize("folder", [RESULTS, QUICK], ids=["full", "quick"])
def test_the_report_reads_as_a_page(folder: Path):
    """The report is a page a person reads (issue 47): short, numbers rounded, no names from the code."""
    report, details = (folder / "report.md").read_text(), (folder / "details.md").read_text()
    assert len(report.split()) <= 4500
    for text in (report, details):
        assert not re.search(r"\d\.\d{7,}", text)  # no float printed raw
        assert not re.search(r"\b(?:figures|suites|metrics|experiments|neurowalk)\.[a-z_]+", text)  # no module path
        assert not re.search(r"\b[a-z]+_[a-z_]+\(", text)  # no function call


@pytest.mark.parametrize("folder", [RESULTS, QUICK], ids=["full", "quick"])
def test_every_claim_not_reproduced_carries_its_cause(folder: Path):
    """Issue 59: each claim that is not reproduced says why (one of the causes' kinds, with its measurement), in its
    record, in the report's table and details and in reproduce.json; a reproduced one carries none."""
    from neurowalk.experiments.reproduce.causes import KINDS

    summary = json.loads((folder / "reproduce.json").read_text())
    listed = {(x["result"], x["what"]): x["cause"] for x in summary["not_reproduced"]}
    details = (folder / "details.md").read_text()
    for item in PLAN:
        rec = json.loads((folder / f"{item.name}.json").read_text())
        for c in rec["claims"]:
            if c["verdict"] == "reproduced":
                assert c["cause"] is None, (item.name, c["what"])
                continue
            assert c["cause"]["kind"] in KINDS and c["cause"]["why"], (item.name, c["what"])
            assert listed[(item.name, c["what"])] == c["cause"]
            assert f"Cause: *{c['cause']['kind']}*: {c['cause']['why']}." in details
    assert len(listed) == summary["claims"]["total"] - summary["claims"]["reproduced"]
