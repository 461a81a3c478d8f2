"""The escape map's machinery on a shrunken sweep (the full sweep is `neurowalk figure escape-map`)."""

from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import escape_map


def test_escape_map_counts_every_network_and_size(monkeypatch, tmp_path):
    monkeypatch.setattr(escape_map, "TRAP_STEPS", 150)
    monkeypatch.setattr(escape_map, "SWEEPS", {"simple-deadlock width (m)": ("simple-deadlock", "width", (0.8, 1.4))})
    res = escape_map.run(Settings(seeds=1))
    counts = res.summary["counts"]["simple-deadlock width (m)"]
    assert set(counts) == {"plastic", "static", "braitenberg"}
    for net in counts.values():
        assert set(net) == {"0.8", "1.4"} and all(c["runs"] == 1 for c in net.values())
    fig = FIGURES["escape-map"].plot(res)
    fig.savefig(tmp_path / "map.png")
    assert (tmp_path / "map.png").stat().st_size > 10_000


def test_escape_map_counts_each_run_under_its_network_and_size(monkeypatch):
    monkeypatch.setattr(escape_map, "SWEEPS", {"simple-deadlock width (m)": ("simple-deadlock", "width", (0.8, 1.4))})

    def stored_runs(configs, *args, **kwargs):  # the plastic network escapes the narrow one only, and from seed 1
        return [
            {"escaped": c.controller == "plastic" and c.arena_opts["width"] == 0.8 and c.seed >= 1} for c in configs
        ]

    monkeypatch.setattr(escape_map, "stored_runs", stored_runs)
    res = escape_map.run(Settings(seeds=3))
    counts = res.summary["counts"]["simple-deadlock width (m)"]
    assert counts["plastic"] == {"0.8": {"runs": 3, "escaped": 2}, "1.4": {"runs": 3, "escaped": 0}}
    assert all(c == {"runs": 3, "escaped": 0} for net in ("static", "braitenberg") for c in counts[net].values())


def test_escape_map_runs_at_the_control_rate(monkeypatch):
    seen = []

    def stored_runs(configs, *args, **kwargs):
        seen.extend(configs)
        return [{"escaped": False} for _ in configs]

    monkeypatch.setattr(escape_map, "stored_runs", stored_runs)
    res = escape_map.run(Settings(quick=True, control_hz=20.0))
    assert seen and all(c.control_hz == 20.0 and c.steps == escape_map.TRAP_STEPS for c in seen)
    assert res.summary["control_hz"] == 20.0 and res.summary["seconds"] == escape_map.TRAP_STEPS / 20.0
    assert res.summary["seeds"] == escape_map.QUICK_SEEDS and res.summary["quick"] is True
