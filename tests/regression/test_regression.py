"""The regression list reproduces every recorded hash (issue 27: a redesign changes no result)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

from cases import CASES, fingerprint

RECORDED = json.loads(Path(__file__).with_name("hashes.json").read_text())


def test_the_list_covers_the_recorded_cases_and_at_least_30_runs():
    assert set(RECORDED["hashes"]) == set(CASES) and len(CASES) >= 30


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_case_reproduces_its_recorded_hash(name, tmp_path):
    if fingerprint() != RECORDED["fingerprint"]:
        pytest.skip(f"hashes recorded with {RECORDED['fingerprint']}, this is {fingerprint()}: floating point may "
                    "differ; record them here with `python tests/regression/record.py` before a redesign")  # fmt: skip
    if name.startswith("gym-"):
        pytest.importorskip("gymnasium")
    assert CASES[name](tmp_path) == RECORDED["hashes"][name]
