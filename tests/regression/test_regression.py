"""The regression list: every recorded hash on the CPU it was recorded on, and what holds on any x86 machine.

Exact hashes (issue 27: a redesign changes no result) hold for the same versions and the same CPU type
(:func:`cases.fingerprint`); on another CPU they skip with a reason that names both CPUs. The portable checks run
everywhere:

* **Outcomes** (escaped, trapped, wedged periods, a sweep's counts, a figure's json less its floats) agree exactly.
* **Heads**: the first :data:`cases.HEAD` rows of each case's floating-point arrays (pose, inputs, outputs, weights;
  a figure's floats; observations and rewards) agree to :data:`RTOL` and :data:`ATOL`. The tolerance, argued: the
  dynamics do not depend on the CPU (MuJoCo's C code is compiled once, with no kernels chosen at run time; numba
  compiles without fast-math, so it neither contracts a*b+c into an FMA nor reorders a sum, whatever the target);
  what does is numpy's SIMD transcendental functions (within 1-4 ulp, by numpy's documentation) and OpenBLAS's order
  of summation, applied to values of order 1-10 (metres, radians, activities in [-1, 1], weights up to about 10):
  a few 1e-15 at most. Measured, emulating another CPU (numba's target znver3, numpy's AVX-512 kernels off,
  OpenBLAS's Zen kernels, against this Zen 4): at most 2.2e-16, in the yaw of the pose, and outcomes equal; the
  same emulation changes exactly the ten hashes that differed on a real Zen 3 machine. 1e-9 leaves six orders of
  magnitude for a difference that would enter the loop and grow before contacts amplify it, and still catches a
  real change: :func:`test_the_heads_tolerance_catches_a_change_of_a_millionth` shows that a millionth of a change
  in the network's inputs moves its outputs beyond it (by 5e-7).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

from cases import CASES, Result, fingerprint

HERE = Path(__file__).parent
RECORDED = json.loads((HERE / "hashes.json").read_text())
#: Relative and absolute tolerance of the heads (the module doc argues them).
RTOL, ATOL = 1e-9, 1e-9


def _heads(name: str) -> dict[str, np.ndarray]:
    with np.load(HERE / "heads.npz", allow_pickle=False) as z:
        return {key.split("|", 1)[1]: z[key] for key in z.files if key.split("|", 1)[0] == name}


_RESULTS: dict[str, Result] = {}


def _result(name: str, factory: pytest.TempPathFactory) -> Result:
    """The case's result, run once per process (both tests of a case on one worker share it)."""
    if name.startswith("gym-"):
        pytest.importorskip("gymnasium")
    if name not in _RESULTS:
        _RESULTS[name] = CASES[name](factory.mktemp(name))
    return _RESULTS[name]


def _cpu(fp: dict) -> str:
    """The CPU as the fingerprint ``fp`` saw it, in words."""
    simd = ", ".join(fp.get("numpy_simd", ["?"]))
    return f"numba CPU {fp.get('numba_cpu', '?')}, numpy SIMD [{simd}], OpenBLAS {fp.get('openblas_core', '?')}"


def test_the_list_covers_the_recorded_cases_and_at_least_30_runs():
    assert set(RECORDED["hashes"]) == set(CASES) == set(RECORDED["outcomes"]) and len(CASES) >= 30


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_case_agrees_with_its_record_on_any_cpu(name, tmp_path_factory):
    result = _result(name, tmp_path_factory)
    assert result.outcome == RECORDED["outcomes"][name], "an outcome-level value changed"
    heads = _heads(name)
    assert set(result.head) == set(heads)
    for key, recorded in heads.items():
        got = result.head[key]
        assert got.shape == recorded.shape, key
        np.testing.assert_allclose(got, recorded, rtol=RTOL, atol=ATOL, equal_nan=True, err_msg=f"{name}: {key}")


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_case_reproduces_its_recorded_hash_on_its_cpu(name, tmp_path_factory):
    here, there = fingerprint(), RECORDED["fingerprint"]
    if here != there:
        versions = {k: (there.get(k), v) for k, v in here.items() if there.get(k) != v}
        pytest.skip(f"hashes recorded with {_cpu(there)}; this machine has {_cpu(here)} (differing: {versions}): "
                    "its bits may differ; the portable checks hold here; record with "
                    "`python tests/regression/record.py` before a redesign")  # fmt: skip
    assert _result(name, tmp_path_factory).sha256 == RECORDED["hashes"][name]


def test_the_heads_tolerance_catches_a_change_of_a_millionth():
    from neurowalk.neural.sensory import simulate

    inputs = np.clip(np.random.default_rng(1).normal(0, 0.7, (400, 2)), -1, 1)
    base = simulate(inputs, mode="plastic").outputs[:50]
    nudged = simulate(inputs * (1 - 1e-6), mode="plastic").outputs[:50]
    assert not np.allclose(nudged, base, rtol=RTOL, atol=ATOL)
