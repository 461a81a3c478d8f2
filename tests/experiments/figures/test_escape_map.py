"""The escape map's machinery on a shrunken sweep (the full sweep is `neurowalk figure escape-map`)."""

from fake_runs import fake_measure, summary_of
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import escape_map
from neurowalk.experiments.study import compute


def test_escape_map_counts_every_network_and_size(monkeypatch, tmp_path):
    monkeypatch.setattr(escape_map, "TRAP_STEPS", 150)
    monkeypatch.setattr(escape_map, "SWEEPS", {"simple-deadlock width (m)": ("simple-deadlock", "width", (0.8, 1.4))})
    res = compute(FIGURES["escape-map"], Settings(seeds=1))
    counts = res.summary["counts"]["simple-deadlock width (m)"]
    assert set(counts) == {"plastic", "static", "braitenberg"}
    for net in counts.values():
        assert set(net) == {"0.8", "1.4"} and all(c["runs"] == 1 for c in net.values())
    fig = FIGURES["escape-map"].plot(res)
    fig.savefig(tmp_path / "map.png")
    assert (tmp_path / "map.png").stat().st_size > 10_000


def test_escape_map_counts_each_run_under_its_network_and_size(monkeypatch):
    monkeypatch.setattr(escape_map, "SWEEPS", {"simple-deadlock width (m)": ("simple-deadlock", "width", (0.8, 1.4))})

    def summary(c):  # the plastic network escapes the narrow one only, and from seed 1
        return summary_of(c, escaped=c.controller == "plastic" and c.arena_opts["width"] == 0.8 and c.seed >= 1)

    _, res = fake_measure("escape-map", Settings(seeds=3), summary)
    counts = res.summary["counts"]["simple-deadlock width (m)"]
    assert counts["plastic"] == {"0.8": {"runs": 3, "escaped": 2}, "1.4": {"runs": 3, "escaped": 0}}
    assert all(c == {"runs": 3, "escaped": 0} for net in ("static", "braitenberg") for c in counts[net].values())


def test_escape_map_runs_at_the_control_rate():
    seen, res = fake_measure(
        "escape-map", Settings(quick=True, control_hz=20.0), lambda c: summary_of(c, escaped=False)
    )
    assert seen and all(c.control_hz == 20.0 and c.steps == escape_map.TRAP_STEPS for c in seen)
    assert res.summary["control_hz"] == 20.0 and res.summary["seconds"] == escape_map.TRAP_STEPS / 20.0
    assert res.summary["seeds"] == escape_map.QUICK_SEEDS and res.summary["quick"] is True
