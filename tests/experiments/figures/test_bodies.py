"""`neurowalk figure bodies`: the suite on every body, from one store; the picture redrawn from its numbers."""

from __future__ import annotations

import json

from neurowalk.cli import main


def test_quick_figure_runs_every_body_and_network_and_redraws(tmp_path):
    assert main(["figure", "bodies", "--quick", "--seeds", "1", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "bodies.json").read_text())
    assert {(r["body"], r["network"]) for r in s["rows"]} == {
        (b, n) for b in ("amosii", "wheeled", "wheeled x0.5") for n in ("plastic", "static", "braitenberg")
    }
    for r in s["rows"]:
        lo, hi = r["table2_ci95"]
        assert r["table2_environments"] == 5 and lo <= r["table2_rate"] <= hi
        assert set(r["dead_ends"]) == {"simple-deadlock", "narrow-passage", "corner"}
    assert s["bodies"]["wheeled x0.5"] == {"body": "wheeled", "body_opts": {"scale": 0.5}}
    png = tmp_path / "bodies.png"
    png.unlink()
    assert main(["figure", "bodies", "--replot", "--out", str(tmp_path)]) == 0 and png.stat().st_size > 50_000
