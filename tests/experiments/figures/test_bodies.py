"""`neurowalk figure bodies`: the suite on every body, from one store; the picture redrawn from its numbers."""

from __future__ import annotations

import json

import pytest

from neurowalk.cli import main
from neurowalk.experiments import Settings
from neurowalk.experiments.figures import bodies


def test_quick_figure_runs_every_body_and_network_and_redraws(tmp_path):
    assert main(["figure", "bodies", "--quick", "--seeds", "1", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "bodies.json").read_text())
    assert {(r["body"], r["network"]) for r in s["rows"]} == {
        (b, n) for b in ("amosii", "wheeled", "wheeled x0.5") for n in ("plastic", "static")
    }
    assert s["control_hz"] == 10.0 and s["coverage_cell_m"] == 0.25
    assert s["coverage_threshold"] == pytest.approx(0.0025)  # 2.5% per 1000 s, in a quick run's 100 s
    for r in s["rows"]:
        lo, hi = r["table2_ci95"]
        assert r["table2_environments"] == 5 and lo <= r["table2_rate"] <= hi
        lo, hi = r["table2_coverage_ci95"]
        assert lo <= r["table2_coverage_rate"] <= hi
        assert r["table2_success_coverage"] + r["table2_failure_coverage"] == 5
        assert r["table2_coverage_quartiles"][0] <= r["table2_median_coverage"] <= r["table2_coverage_quartiles"][1]
        assert 0 <= r["table2_held_up_300s_success"] <= r["table2_success"]
        assert set(r["dead_ends"]) == {"simple-deadlock", "narrow-passage", "corner"}
    assert s["bodies"]["wheeled x0.5"] == {"body": "wheeled", "body_opts": {"scale": 0.5}}
    png = tmp_path / "bodies.png"
    png.unlink()
    assert main(["figure", "bodies", "--replot", "--out", str(tmp_path)]) == 0 and png.stat().st_size > 50_000


def test_control_hz_reaches_every_dead_end_and_table_run() -> None:
    p = bodies.plan(Settings(quick=True, seeds=1, control_hz=27.0))
    specs = [*p["dead"].values(), *p["table"].values()]
    assert {s["control_hz"] for s in specs} == {27.0}
    assert p["dead_steps"] == 1620 and p["t2_steps"] == 2700  # 60 s and 100 s at 27 Hz
    half = {s["steps"] for s in p["dead"].values() if s.get("body_opts")}
    assert half == {3240}  # the half-size robot: twice as long
    at10 = bodies.plan(Settings(seeds=1))
    assert at10["dead_steps"] == 5000 and at10["t2_steps"] == 20_000
