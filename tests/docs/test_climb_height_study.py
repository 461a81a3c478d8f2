"""The climb-height study (docs/studies/climb_height.py): it loads, runs, and its quick version shows the behaviour."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from doc_blocks import ROOT

from neurowalk import Settings, load_study, run_study

FILE = ROOT / "docs/studies/climb_height.py"


@pytest.mark.slow
def test_the_study_climbs_a_6_cm_step_every_time_a_12_cm_one_never_and_never_better_higher(tmp_path: Path) -> None:
    result, files = run_study(load_study(FILE), Settings(quick=True, out=tmp_path))
    s = result.summary
    assert s["heights_m"] == [0.06, 0.12] and s["seeds"] == 2
    assert s["--climb"]["climbed"] == [2, 0]  # 12 cm is above the backbone control's climbable limit: a wall
    assert s["--climb"]["highest_every_seed_m"] == 0.06
    assert s["--reflexes"]["climbed"][1] == 0  # without backbone control the network avoids what its sensors see
    assert s["--climb"]["largest_rise"] == s["--reflexes"]["largest_rise"] == 0.0
    assert {p.name for p in files.values()} == {"climb-height.png", "climb-height.json"}


@pytest.mark.slow
@pytest.mark.parametrize("label", [("--climb", 0.11), ("--climb", 0.12), ("--reflexes", 0.06)])
def test_a_committed_all_or_none_count_holds_for_its_first_seed_run_again(label: tuple[str, float]) -> None:
    from neurowalk.sim.episode import run_episode

    committed = json.loads((ROOT / "docs/studies/climb-height/climb-height.json").read_text())
    count = committed[label[0]]["climbed"][committed["heights_m"].index(label[1])]
    assert count in (0, committed["seeds"])  # the cases chosen: every seed climbed, or none
    cfg = next(p.config for p in load_study(FILE).runs(Settings()) if p.label == label)
    assert cfg.seed == 0
    assert (run_episode(cfg).summary["exit_step"] is not None) == (count > 0)
