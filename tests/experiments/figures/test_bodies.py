"""`neurowalk figure bodies`: the suite on every body, from one store; the picture redrawn from its numbers."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fake_runs import fake_measure, summary_of
from neurowalk.cli import main
from neurowalk.experiments import Settings
from neurowalk.experiments.figures import bodies
from neurowalk.experiments.suites.random_envs import wilson
from neurowalk.sim.config import EpisodeConfig


def test_quick_figure_runs_every_body_and_network_and_redraws(tmp_path):
    assert main(["figure", "bodies", "--quick", "--seeds", "1", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "bodies.json").read_text())
    assert {(r["body"], r["network"]) for r in s["rows"]} == {
        (b, n) for b in ("amosii", "wheeled", "wheeled x0.5") for n in ("plastic", "static")
    }
    assert s["control_hz"] == 10.0 and s["coverage_cell_m"] == 0.25
    assert s["coverage_threshold"] == pytest.approx(0.0025)  # 2.5% per 1000 s, in a quick run's 100 s
    for r in s["rows"]:  # each row's numbers from its own runs: test_each_row_counts_its_own_table2_runs
        assert r["table2_environments"] == 5
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


def test_each_row_counts_its_own_table2_runs() -> None:
    """Stand-in runs: in the k-th row (body, network), environments 0 to k - 1 end stuck and environment i covers
    (i + k) / 1000 of the arena; each row's Table 2 numbers are those of its own runs, counted here."""
    s = Settings(quick=True, seeds=1)
    envs = [e["seed"] for e in bodies.plan(s)["envs"]]
    rows = [(b, net) for b in bodies.BODIES for net in bodies.NETWORKS]
    named = {(body, tuple(opts.items())): b for b, (body, opts) in bodies.BODIES.items()}

    def summary(cfg: EpisodeConfig) -> dict:
        k = rows.index((named[cfg.body, tuple(cfg.body_opts.items())], cfg.controller))
        i = envs.index(cfg.seed) if cfg.arena == "random" else 0
        return summary_of(cfg, trapped=i < k, coverage=(i + k) / 1000)

    _, res = fake_measure("bodies", s, summary)
    threshold = res.summary["coverage_threshold"]  # 2.5/1000: covered from environment 3 - k on
    assert len(envs) == 5 and [(r["body"], r["network"]) for r in res.summary["rows"]] == rows
    for k, r in enumerate(res.summary["rows"]):
        coverage = [(i + k) / 1000 for i in range(5)]
        ok, covered = max(0, 5 - k), sum(c >= threshold for c in coverage)
        assert (r["table2_success"], r["table2_failure"], r["table2_rate"]) == (ok, 5 - ok, ok / 5)
        assert r["table2_ci95"] == list(wilson(ok, 5))
        assert (r["table2_success_coverage"], r["table2_failure_coverage"]) == (covered, 5 - covered)
        assert r["table2_coverage_ci95"] == list(wilson(covered, 5))
        assert r["table2_median_coverage"] == pytest.approx(np.median(coverage))
