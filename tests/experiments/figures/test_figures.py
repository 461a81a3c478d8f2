"""Figures 2 and 4 from the command line, as a user runs them."""

import dataclasses
import json

import numpy as np
import pytest
from matplotlib.image import imread

from fake_runs import plan
from neurowalk.cli import main


@pytest.fixture(scope="module")
def fig4(tmp_path_factory):
    out = tmp_path_factory.mktemp("fig4")
    assert main(["figure", "fig4", "--out", str(out), "--quick"]) == 0
    return out


def test_fig4_writes_files_and_converges_from_every_start(fig4):
    assert (fig4 / "fig4.png").stat().st_size > 10_000
    s = json.loads((fig4 / "fig4.json").read_text())
    assert len(s["panel_a"]["starts"]) >= 4
    for run in s["panel_a"]["starts"]:
        assert run["b1"] == pytest.approx(s["fixed_points"]["b"], rel=0.01)
        assert run["q1"] == pytest.approx(s["fixed_points"]["q"], rel=0.01)
    assert s["fixed_points"]["b"] == pytest.approx(4.63, abs=0.01)
    # Panel B: growth while the reflex is on is much faster than decay after it.
    b = s["panel_b"]
    assert b["growth_to_decay_ratio"] > 5
    # ... on inputs recorded in a physics run, which the offline replay reproduces
    assert (b["arena"], b["body"], b["steps"], b["seed"], b["control_hz"]) == ("difficult", "amosii", 3000, 0, 10.0)
    assert b["replay_max_abs_diff_from_run"] < 1e-9
    assert {e["side"] for e in b["episodes"]} >= {"left", "right"}  # walls met on both sides


def test_fig4_panel_b_runs_at_the_figures_control_rate(monkeypatch):
    from neurowalk.experiments import Settings
    from neurowalk.experiments.figures import fig4

    (p,) = plan("fig4", Settings(quick=True, seed=3, control_hz=27.0))
    cfg = p.config
    assert (cfg.control_hz, cfg.seed, cfg.steps, cfg.arena, cfg.controller) == (27.0, 3, 3000, "difficult", "plastic")
    assert (cfg.b0, cfg.q0) == fig4.PAPER_START


def test_fig4_replot_and_seed_determinism(fig4, tmp_path):
    before = (fig4 / "fig4.json").read_text()
    assert main(["figure", "fig4", "--out", str(fig4), "--replot"]) == 0
    assert (fig4 / "fig4.json").read_text() == before
    assert main(["figure", "fig4", "--out", str(tmp_path), "--quick"]) == 0
    assert (tmp_path / "fig4.json").read_text() == before


def test_a_replot_that_fails_in_the_drawing_says_where(fig4, tmp_path, monkeypatch, capsys):
    import shutil

    from neurowalk.experiments import FIGURES

    shutil.copytree(fig4, tmp_path / "fig4")
    broken = dataclasses.replace(FIGURES["fig4"], plot=lambda result: result.summary["no such key"])
    monkeypatch.setitem(FIGURES, "fig4", broken)
    assert main(["figure", "fig4", "--out", str(tmp_path / "fig4"), "--replot"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "KeyError: 'no such key', at test_figures.py:" in err and "<lambda>" in err


def test_fig2_thresholds_and_widths(tmp_path):
    assert main(["figure", "fig2", "--out", str(tmp_path), "--quick"]) == 0
    s = json.loads((tmp_path / "fig2.json").read_text())
    rows = s["single_neuron"]
    small = [r for r in rows if r["b"] <= 1.0]
    assert small and all(r["width"] < 0.01 for r in small)
    growing = [r["width"] for r in rows if r["b"] >= 1.25 and r["width"] is not None]
    assert bool(np.all(np.diff(growing) > 0))
    # each measured switch-on input is the analytic one of the same b, within a step of the quick sweep's 101 levels
    hysteretic = [r for r in rows if r["switch_on_analytic"] is not None]
    assert hysteretic and all(abs(r["switch_on"] - r["switch_on_analytic"]) < 2 / 100 for r in hysteretic)
    with np.load(tmp_path / "fig2.npz") as z:  # panel D (b = 8): no input in [-1, 1] turns the neuron on
        levels, out = z["n2_levels"], z["n2_out"]
    assert (levels.min(), levels.max()) == (-1.0, 1.0) and bool(np.all(out < 0))
    picture = imread(tmp_path / "fig2.png")  # a drawing, not a blank page
    assert min(picture.shape[:2]) > 500 and picture[..., :3].std() > 0.05


def test_unknown_figure_exits_2_with_one_line(capsys, tmp_path):
    assert main(["figure", "fig99", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "fig99" in err[0]
    assert not any(tmp_path.iterdir())


def test_bad_arguments_exit_2(capsys):
    assert main(["figure"]) == 2
    assert main(["figure", "fig2", "--seed", "-3"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 2


def test_fig2_stable_fixed_points_are_marked_on_top_of_the_sweeps():
    from neurowalk.experiments import Settings
    from neurowalk.experiments.figures import fig2
    from neurowalk.neural.analysis import single_neuron_branches

    res = fig2.measure(Settings(quick=True), {})
    figure = fig2.plot(res)
    d = figure.axes[3]
    assert d.get_title() == "one neuron, b = 8.0"
    sweeps = [line for line in d.get_lines() if "sweep" in line.get_label()]
    marks = [line for line in d.get_lines() if line.get_marker() == "o" and len(line.get_xdata())]
    assert len(marks) == 2 and all(m.get_zorder() > max(s.get_zorder() for s in sweeps) for m in marks)
    ys = sorted(float(np.mean(m.get_ydata())) for m in marks)  # one marked branch at -1, one at +1
    assert ys == pytest.approx([-1.0, 1.0], abs=0.003)
    assert all(len(m.get_xdata()) == len(fig2.STABLE_MARKS) for m in marks)  # across the whole panel
    legend = d.get_figure(root=False).legends[0]  # the top row's legend, under B-D
    handles, labels = legend.legend_handles, [t.get_text() for t in legend.get_texts()]
    assert labels[0] == fig2.STABLE_LABEL and handles[0].get_marker() == "o"
    runs = fig2.stable_branches(*single_neuron_branches(8.0))  # its two stable branches span the whole panel
    assert len(runs) == 2
    for i, o in runs:
        assert bool(np.all(np.diff(i) >= 0)) and i[0] <= -1.0 <= 1.0 <= i[-1]
        assert bool(np.all(np.abs(o[(i >= -1) & (i <= 1)]) > 0.997))
