"""The authors' simulator as the second reference: its data ship with the package, load with their columns, and
measured by neurowalk's rules give what their runs show (directions, CPG period, dead ends, long runs); the report
and the committed records carry it."""

from __future__ import annotations

import dataclasses
import fnmatch
import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

import neurowalk
from neurowalk.experiments.reproduce import authors
from neurowalk.experiments.reproduce.judge_authors import RULES, compare
from neurowalk.experiments.reproduce.plan import ITEMS
from neurowalk.experiments.reproduce.report import render
from neurowalk.neural.cpg import period, simulate_cpg

ROOT = Path(__file__).parents[3]
RESULTS = ROOT / "docs" / "results"


def test_the_data_lie_in_the_package_and_pyproject_ships_every_file():
    package = Path(neurowalk.__file__).parent
    assert authors.DATA.is_dir() and authors.DATA.is_relative_to(package)
    globs = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]["neurowalk"]
    files = [p.relative_to(package).as_posix() for p in authors.DATA.rglob("*") if p.is_file()]
    assert len(files) > 25 and "experiments/reproduce/authors_simulator/README.md" in files
    unshipped = [f for f in files if not any(fnmatch.fnmatch(f, g) and f.count("/") == g.count("/") for g in globs)]
    assert unshipped == []
    assert sum(p.stat().st_size for p in authors.DATA.rglob("*")) < 3e6


def test_files_load_with_their_columns_and_one_row_per_control_step():
    cases = {
        "flat_ground/forward.csv.gz": ({"x", "y", "yaw", "cpg0"}, 3200),
        "flat_ground/stop.csv.gz": ({"x", "y", "yaw"}, 3200),
        "dead_ends/narrow-passage_plastic_s11.csv.gz": ({"x", "y", "yaw"}, 5000),
        "dead_ends/simple-deadlock_static_s12_1500s.csv.gz": ({"x", "y", "yaw"}, 15001),
        "difficult_arena/static.csv.gz": ({"x", "y", "yaw", "us_L", "us_R"}, 100_000),
    }
    for name, (columns, rows) in cases.items():
        cols = authors.load(name)
        assert set(cols) == columns | {"t"}, name
        assert all(v.shape == (rows,) and np.isfinite(v).all() for v in cols.values()), name
        assert cols["t"][0] == 0.1 and np.allclose(np.diff(cols["t"]), 1 / authors.CONTROL_HZ), name


def test_the_trunk_centre_starts_at_the_arenas_start():
    """The logged rear box sits 0.06 m behind the trunk centre: moved forward, the first row is the start."""
    starts = (
        ("dead_ends/simple-deadlock_static_s10.csv.gz", (0.0, 0.0)),
        ("difficult_arena/plastic.csv.gz", (3.0, -1.0)),
    )
    for name, start in starts:
        first = authors.trunk_pose(authors.load(name))[0]
        assert np.hypot(first[0] - start[0], first[1] - start[1]) < 0.003, name
        rear = authors.load(name)
        assert np.hypot(rear["x"][0] - start[0], rear["y"][0] - start[1]) > 0.05, name


def test_table1_directions_signs_and_names():
    runs = authors.flat_ground()
    assert runs["forward"]["speed_m_per_s"] > 0.005 and runs["backward"]["speed_m_per_s"] < -0.005
    assert runs["turn left"]["turn_rate_deg_per_s"] > 1.0 and runs["turn right"]["turn_rate_deg_per_s"] < -1.0
    assert abs(runs["stop"]["speed_m_per_s"]) < 0.001
    assert all(r["direction"] == r["paper"] for r in runs.values())


def test_the_cpg_period_is_neurowalks_cpg_period_within_two_percent():
    cpg, _ = simulate_cpg(2000)
    ours = period(cpg[500:, 0] - cpg[500:, 0].mean())
    assert abs(authors.cpg_period() - ours) <= 0.02 * ours


def test_dead_ends_static_trapped_in_the_narrow_passage_plastic_escapes_both():
    d = authors.dead_ends()
    narrow = d["narrow-passage"]["static"]
    assert narrow["escaped"] == 0 and narrow["trapped"] == narrow["runs"] == 3
    for arena in authors.DEAD_END_ARENAS:
        cell = d[arena]["plastic"]
        assert cell["escaped"] == cell["runs"] == 3 and len(cell["exit_s"]) == 3
        assert all(0 < t < 500 for t in cell["exit_s"])
    simple = d["simple-deadlock"]["static"]
    assert simple["more"]["runs"] == 10 and simple["escaped"] <= simple["more"]["escaped"] < 10
    assert [r["seed"] for r in simple["long"]] == [10, 12] and all(r["seconds"] > 1000 for r in simple["long"])


def test_long_runs_plastic_explores_static_is_trapped():
    runs = authors.long_runs()
    plastic, static = runs["plastic"], runs["static"]
    assert plastic["seconds"] == static["seconds"] == 10_000
    assert plastic["coverage"] > 5 * static["coverage"] > 0
    assert static["trapped"] and not plastic["trapped"]
    assert static["longest_wedged_s"] > 9000  # trapped from early on to the end
    assert static["held_periods"] > 0 and static["held_over_300s"] > 0  # held still in its pocket
    assert plastic["held_over_300s"] == 0 and plastic["turning_periods"] == plastic["wedged_periods"] > 0


def test_compare_judges_every_comparable_claim_and_nothing_else():
    """Every rule of the authors' runs finds its claim in the committed records; other items get no entry."""
    for name, rules in RULES.items():
        rec = json.loads((RESULTS / f"{name}.json").read_text())
        assert len(rec["authors"]["claims"]) == len(rules), name
        assert {c["what"] for c in rec["authors"]["claims"]} <= {c["what"] for c in rec["claims"]}, name
        assert rec["authors"]["reason"].startswith("the authors' simulator: ")
    assert compare("fig2", {}, []) is None
    fig3 = json.loads((RESULTS / "fig3.json").read_text())["authors"]["claims"]
    simple = next(c for c in fig3 if c["what"].startswith("static network escapes the simple dead end"))
    assert simple["measured"] == f"{authors.dead_ends()['simple-deadlock']['static']['escaped']}/3"


def test_a_reworded_claim_is_not_dropped_from_the_comparison_unseen():
    summary = json.loads((RESULTS / "fig3" / "fig3.json").read_text())
    claims = ITEMS["fig3"].judge(summary, False)
    assert compare("fig3", summary, claims) is not None
    reworded = [dataclasses.replace(c, what="the static robot " + c.what) for c in claims]
    with pytest.raises(ValueError, match="matches none of its claims"):
        compare("fig3", summary, reworded)


def test_the_report_shows_the_authors_column_and_where_the_data_come_from():
    text = render(RESULTS, quick=False)
    assert "| result | the paper | neurowalk: claims reproduced | authors' simulator | verdict | time |" in text
    assert "## The authors' simulator" in text and "94d406a" in text
    row = next(line for line in text.splitlines() if line.startswith("| [table1](#table1)"))
    assert "| 6 of 6 | 5 of 5 | reproduced |" in row  # neurowalk's claims, then the authors' simulator's
