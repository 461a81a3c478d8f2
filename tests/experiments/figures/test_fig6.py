"""Fig. 6: sixteen environments, each run classed (failed, confined space passed, trap escaped, plain success)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from neurowalk.cli import main
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import fig6
from neurowalk.experiments.study import compute
from neurowalk.experiments.suites.confinement import CLASSES, RULE_NUMBERS


def test_fig6_draws_sixteen_environments_classes_them_and_replots(tmp_path: Path) -> None:
    assert main(["figure", "fig6", "--quick", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "fig6.json").read_text())
    assert len(s["environments"]) == 16 and s["body"] == "surrogate" and s["control_hz"] == 10.0
    assert s["success"] == sum(e["success"] for e in s["environments"])
    # the trap's angle is the paper's own trap's (the simple dead end, the same network and body), not a number of ours
    ref = s["trap_reference"]
    assert ref["arena"] == "simple-deadlock" and ref["trap_blocked_deg"] == min(ref["widest_blocked_deg"])
    assert s["class_numbers"] == {**RULE_NUMBERS, "trap_blocked_deg": ref["trap_blocked_deg"]}
    assert f">= {ref['trap_blocked_deg']:g} deg" in s["class_rule"] and "0.6 m" in s["class_rule"]
    h = s["blocked_histogram"]
    assert sum(h["counts"]) == h["environments"] == 100 and 0 <= h["at_least_trap"] <= 100
    assert s["coverage_threshold"] == pytest.approx(0.0125) and s["coverage_cell_m"] == 0.25
    assert sum(s["classes"].values()) == 16 and set(s["classes"]) == set(CLASSES)
    for e in s["environments"]:
        assert e["outcome"] in CLASSES and (e["outcome"] == "failed") == (not e["success"])
        assert e["success_coverage"] == (e["coverage"] >= s["coverage_threshold"])
        assert (e["outcome"] == "escaped a trap") == (e["success"] and e["left_trap"] is not None)
    with np.load(tmp_path / "fig6.npz") as z:
        assert z["env0/pose"].shape == (500, 3)  # 5000 steps, every 10th (one a second at 10 Hz)
    png = tmp_path / "fig6.png"
    png.unlink()
    assert main(["figure", "fig6", "--replot", "--out", str(tmp_path)]) == 0 and png.stat().st_size > 10_000


def test_control_hz_reaches_every_run_of_fig6() -> None:
    specs = fig6.specs(Settings(quick=True, body="amosii", control_hz=27.0))
    assert len(specs) == 16 and {s["control_hz"] for s in specs} == {27.0}
    assert {s["steps"] for s in specs} == {13_500}  # 500 s at 27 Hz
    assert fig6.pose_stride(27.0) == 27 and fig6.pose_stride(10.0) == 10


def test_fig6_on_the_surrogate_refuses_27_hz(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"'surrogate'.*10(\.0)? Hz.*27"):
        compute(FIGURES["fig6"], Settings(quick=True, control_hz=27.0, out=tmp_path / "f6"))
    assert not (tmp_path / "f6").exists()
