"""The committed quick reproduction's numbers come out again (``docs/results/quick``): a redesign changes no
result. The cheaper results' commands are rerun as recorded and each figure's json compared with the committed
one: every count, flag and text exactly, every float within :data:`RTOL` (on another CPU a float may differ in its
last bit: ``docs/usage.md``, "Same seed, same result", measured 2.3e-16 at most)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import pytest

from neurowalk.cli import main

QUICK = Path(__file__).parents[3] / "docs" / "results" / "quick"
#: Results whose quick command takes seconds (the others are covered by `neurowalk reproduce --quick` itself).
CHEAP = ("table1", "fig2", "fig6", "fig7", "table2", "latched-spin")
RTOL = 1e-9
#: Keys that measure the machine or name a folder, not the result; ``sweep``: how the runs were had (made, or taken
#: from the stores the reproduction's figures share), not what they gave; ``code``: the fingerprint of the code.
VOLATILE = ("wall", "time_s", "real_time_factor", "store", "files", "sweep", "code")


def _leaves(v: Any, path: str = "") -> dict[str, Any]:
    """path -> leaf value of a JSON document (lists indexed), the volatile keys left out."""
    out: dict[str, Any] = {}
    if isinstance(v, dict):
        for k, x in v.items():
            if not any(word in k for word in VOLATILE):
                out.update(_leaves(x, f"{path}/{k}"))
    elif isinstance(v, list):
        for i, x in enumerate(v):
            out.update(_leaves(x, f"{path}/{i}"))
    else:
        out[path] = v
    return out


@pytest.mark.parametrize("name", CHEAP)
def test_a_quick_result_comes_out_as_committed(name: str, tmp_path: Path) -> None:
    record = json.loads((QUICK / f"{name}.json").read_text())
    run = record["files"]["json"].split("/")[0]  # the committed settings file, in a fresh folder (and stores) here
    (tmp_path / "settings.json").write_text(json.dumps({"figure": record["figure"], "settings": {
        **record["settings"], "out": str(tmp_path / run), "shared_runs": str(tmp_path / "runs")}}))  # fmt: skip
    assert record["command"].endswith(f"{run}/settings.json")  # the command reads the settings recorded
    assert main(["figure", record["figure"], "--settings", str(tmp_path / "settings.json")]) == 0
    plt.close("all")
    rel = record["files"]["json"]
    got = _leaves(json.loads((tmp_path / rel).read_text()))
    want = _leaves(json.loads((QUICK / rel).read_text()))
    if "/quick" not in want:  # a json of before the stamp: whether it is quick, said by every json now
        assert got.pop("/quick") is True
    assert set(got) == set(want), set(got) ^ set(want)
    for path, w in want.items():
        g = got[path]
        if isinstance(w, float) and isinstance(g, float) and not (math.isnan(w) and math.isnan(g)):
            assert math.isclose(g, w, rel_tol=RTOL, abs_tol=1e-12), f"{name}{path}: {g!r} != {w!r}"
        else:
            assert g == w or (g != g and w != w), f"{name}{path}: {g!r} != {w!r}"
