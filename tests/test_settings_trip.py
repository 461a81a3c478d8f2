"""The settings go down once: followed from `neurowalk figure fig4 --quick`'s arguments, and from `neurowalk run`'s
(benchmarks/settings_trip.py), they stay in at most 20 places and climb back up the layers at most 4 times."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from settings_trip import measure, trip


def test_the_settings_trip_of_a_figure_is_short_and_goes_down(tmp_path: Path) -> None:
    calls = trip("fig4", tmp_path / "fig4")
    m = measure(calls)
    assert m["stays"] <= 20 and m["climbs_back_up"] <= 4, "\n".join(m["trip"])
    assert calls[0][0].startswith("cli/") and ("experiments/figures/fig4.py", "measure") in calls  # followed to the end
    assert not any(f.startswith("runners/store") and fn == "count_finished" for f, fn in calls)  # no CLI count first


def test_the_settings_trip_of_a_run_is_short_and_goes_down(tmp_path: Path) -> None:
    calls = trip("run", tmp_path / "run")
    m = measure(calls)
    assert m["stays"] <= 20 and m["climbs_back_up"] <= 4, "\n".join(m["trip"])
    assert calls[1] == ("cli/run.py", "cmd_run") and ("sim/loop.py", "run_worlds") in calls  # followed to the loop
