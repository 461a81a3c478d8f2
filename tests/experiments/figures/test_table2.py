"""Table 2 under both rules (not stuck; coverage), the held-up count, the control rate, the picture from its json."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from neurowalk.cli import main
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import table2
from neurowalk.experiments.study import compute
from neurowalk.experiments.suites.random_envs import coverage_threshold, environments, outcome, row_counts, spec, wilson
from neurowalk.runners.specs import spec_key


def _summary(trapped: bool, coverage: float, **more: Any) -> dict[str, Any]:
    """A run's summary with what Table 2 reads of it."""
    return {
        "trapped": trapped,
        "coverage": coverage,
        "ever_trapped": False,
        "ever_held_up_1000s": False,
        "longest_wedged_s": 0.0,
        "longest_held_s": 0.0,
        "path_length_m": 20.0,
        "end_turn_share": 0.1,
        "end_blind_share": 0.1,
        **more,
    }


def test_both_rules_are_counted_from_the_runs() -> None:
    runs = [
        _summary(False, 0.01, ever_trapped=True),  # not stuck at the end, little covered; held up on the way
        _summary(True, 0.08, end_turn_share=0.9),  # stuck at the end (latched spin) after covering much
        _summary(False, 0.05),  # both: the threshold counts as reached
        _summary(False, 0.0499),  # not stuck, just below the threshold
        _summary(True, 0.02, end_blind_share=0.7),  # neither (wedged)
        _summary(False, 0.11, longest_wedged_s=320.0, longest_held_s=320.0),  # both; held for 320 s on the way
    ]
    rows = [{"seed": i, "n_boxes": 5, "net": outcome(r, 0.05)} for i, r in enumerate(runs)]
    assert [r["net"]["success_coverage"] for r in rows] == [False, True, True, False, False, True]
    c = row_counts(rows, "net")
    assert (c["success"], c["failure"], c["success_coverage"], c["failure_coverage"]) == (4, 2, 3, 3)
    assert (c["success_both"], c["success_not_stuck_only"], c["success_coverage_only"]) == (2, 2, 1)
    assert c["success_coverage_rate"] == 0.5 and c["success_coverage_rate_95ci"] == list(wilson(3, 6))
    assert c["success_rate_95ci"] == list(wilson(4, 6))
    assert c["held_up_300s_success"] == 2 and c["ever_held_up_300s"] == 1
    assert c["failure_classes"] == {"latched spin": 1, "wedged": 1, "other": 0}
    assert c["median_coverage"] == pytest.approx(0.04995)
    assert c["coverage_quartiles"] == pytest.approx([0.027475, 0.0725])  # numpy's linear quartiles


def test_the_coverage_threshold_scales_with_the_simulated_time() -> None:
    assert coverage_threshold(2000.0) == pytest.approx(0.05) and coverage_threshold(500.0) == pytest.approx(0.0125)


def test_control_hz_reaches_every_spec_and_keeps_the_durations_in_seconds() -> None:
    p = table2.plan(Settings(quick=True, seeds=2, body="amosii", control_hz=27.0))
    specs = list(p["specs"].values())
    assert {s["control_hz"] for s in specs} == {27.0} and {s["steps"] for s in specs} == {13_500}
    assert p["bodies"] == ["amosii"] and p["surrogate"] is None  # the surrogate runs at 10 Hz only
    assert "'surrogate'" in p["surrogate_note"] and "10 Hz" in p["surrogate_note"]
    at10 = table2.plan(Settings(quick=True, seeds=2, body="amosii"))
    assert at10["bodies"] == ["amosii", "surrogate"] and at10["surrogate_note"] is None
    specs10 = list(at10["specs"].values())
    assert {s["steps"] for s in specs10} == {5000} and {s["control_hz"] for s in specs10} == {10.0}
    e = environments(1, 0)[0]  # the rate named at its default: the key of the runs stored before it was named
    plain = spec(e, "plastic", 100, "surrogate")
    assert spec_key(plain) == spec_key({k: v for k, v in plain.items() if k != "control_hz"})


@pytest.mark.parametrize("body", ["surrogate", "surrogate-wheeled"])
def test_a_surrogate_refuses_another_rate_before_any_run(body: str, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=rf"'{body}'.*calibrated at 10(\.0)? Hz.*27"):
        compute(FIGURES["table2"], Settings(quick=True, seeds=1, body=body, control_hz=27.0, out=tmp_path / "t2"))
    assert not (tmp_path / "t2").exists()


def test_quick_table_json_has_both_rules_and_replots(tmp_path: Path) -> None:
    assert main(["figure", "table2", "--quick", "--seeds", "3", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "table2.json").read_text())
    assert s["control_hz"] == 10.0 and s["duration_s"] == 500.0 and s["stuck_window_s"] == 300.0
    assert s["coverage_cell_m"] == 0.25 and s["coverage_threshold"] == pytest.approx(0.0125)
    assert "1.25%" in s["coverage_rule"] and "0.25 m" in s["coverage_rule"] and "held up" in s["held_up_rule"]
    for name, c in s["counts"].items():
        runs = [e[name] for e in s["environments"]]
        # each row counts the environments' outcomes listed beside it (row_counts' intervals and quartiles:
        # test_both_rules_are_counted_from_the_runs)
        assert c["environments"] == len(runs) == 3 and c["success"] == sum(r["success"] for r in runs)
        assert c["success_coverage"] == sum(r["coverage"] >= s["coverage_threshold"] for r in runs)
        assert c["median_coverage"] == pytest.approx(np.median([r["coverage"] for r in runs]))
        assert c["held_up_300s_success"] == sum(r["success"] and r["held_up_300s"] for r in runs)
        assert all({"coverage", "success", "success_coverage", "held_up_300s"} <= set(r) for r in runs)
    png = tmp_path / "table2.png"
    png.unlink()
    assert main(["figure", "table2", "--replot", "--out", str(tmp_path)]) == 0 and png.stat().st_size > 50_000


def test_under_shared_runs_the_json_names_the_store_that_holds_its_runs(tmp_path: Path) -> None:
    from neurowalk.runners.store import count_finished

    out, runs = tmp_path / "table2", tmp_path / "runs"
    assert main(["figure", "table2", "--quick", "--seeds", "2", "--out", str(out), "--shared-runs", str(runs)]) == 0
    store = Path(json.loads((out / "table2.json").read_text())["store"])
    assert store.parent == runs and count_finished(store) == len(table2.plan(Settings(quick=True, seeds=2))["specs"])


def test_the_braitenberg_row_runs_on_the_surrogate_only() -> None:
    physics = table2.plan(Settings(body="amosii", quick=True))
    surrogate = table2.plan(Settings(quick=True))
    assert table2.SURROGATE_ONLY in surrogate["table"] and table2.SURROGATE_ONLY not in physics["table"]
    assert {"plastic-paper", "plastic-original", "static"} <= set(physics["table"])
    physics_rows = {
        (s["controller"], s.get("variant", "paper")) for s in physics["specs"].values() if s["body"] == "amosii"
    }
    assert ("braitenberg", "paper") not in physics_rows
    assert any(s["controller"] == "braitenberg" for s in surrogate["specs"].values())
