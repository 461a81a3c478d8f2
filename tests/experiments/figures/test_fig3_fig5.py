"""Fig. 3 and Fig. 5: the long runs' length by the stated reading of "time step", the control rate in every run,
the panels named as the paper names them, and Fig. 5G's weights over the whole long run.

The figures' runs are replaced by stand-ins here (:mod:`fake_runs`), except in the streamed long-run tests, which
run a few thousand control steps.
"""

import numpy as np
import pytest

from fake_runs import fake_measure, plan
from neurowalk.experiments import Settings
from neurowalk.experiments.figures import fig3, fig5
from neurowalk.experiments.reproduce import authors
from neurowalk.experiments.study_runs import run_kept
from neurowalk.experiments.suites import deadends, long_runs
from neurowalk.experiments.suites.long_runs import saturating_fit
from neurowalk.plotting.style import LETTER_GID
from neurowalk.runners.specs import result_of
from neurowalk.sim.episode import EpisodeConfig


def run(fig, s: Settings, seen: list[EpisodeConfig] | None = None):
    """Fig. 3's or Fig. 5's measure of stand-in runs (:mod:`fake_runs`); the configs it asked for into ``seen``."""
    configs, res = fake_measure(fig.NAME, s)
    if seen is not None:
        seen.extend(configs)
    return res


def test_the_long_runs_are_the_papers_time_steps_read_as_physics_steps():
    # Fig. 5: 1,000,000 time steps; Fig. 3: 70,000 + 330,000 (the green dot at 70,000): ten physics steps to a
    # control step in the authors' simulator (controlinterval 10 of 0.01 s).
    assert long_runs.PHYSICS_PER_CONTROL == 10
    assert fig5.LONG_STEPS == 100_000 and fig3.LONG_STEPS == 40_000 and fig3.MARK_STEP == 7_000
    assert deadends.TRAP_STEPS == 5000  # the dead ends' 5000 time steps are control steps
    assert long_runs.QUICK_LONG_STEPS < fig3.LONG_STEPS


@pytest.mark.parametrize(("fig", "quick", "long_steps"), [
    (fig5, False, 100_000), (fig5, True, long_runs.QUICK_LONG_STEPS),
    (fig3, False, 40_000), (fig3, True, long_runs.QUICK_LONG_STEPS),
])  # fmt: skip
def test_every_run_gets_the_control_rate_and_the_long_runs_their_length(fig, quick, long_steps):
    faked: list[EpisodeConfig] = []
    res = run(fig, Settings(quick=quick, seeds=1, control_hz=20.0), faked)
    assert faked and all(c.control_hz == 20.0 for c in faked)
    long_cfgs = [c for c in faked if c.arena in ("cluttered", "difficult")]
    dead_ends = [c for c in faked if c.arena not in ("cluttered", "difficult")]
    seeds = fig.COVERAGE_SEEDS[quick] - 1 if fig is fig5 else 0  # Fig. 5F's further seeds of the plastic run
    assert len(long_cfgs) == len(fig.LONG) + seeds and all(c.steps == long_steps for c in long_cfgs)
    assert dead_ends and all(c.steps == 5000 for c in dead_ends)  # control steps at any rate
    s = res.summary
    assert s["control_hz"] == 20.0 and s["table"]["control_hz"] == 20.0 and s["table"]["seconds"] == 250.0
    assert s["quick"] is quick and s["long_steps"] == long_steps and s["long_s"] == long_steps / 20.0
    assert s["long_steps_full"] == fig.LONG_STEPS
    reading = s["time_step_reading"]
    assert reading["physics_per_control_step"] == 10 and reading["this_run_long_steps"] == long_steps
    assert sum(reading["control_steps"].values()) == fig.LONG_STEPS
    assert sum(reading["paper_time_steps"].values()) == fig.LONG_STEPS * 10
    if fig is fig3:
        assert s["mark_step"] == 7_000  # below the quick runs' length too
    if quick:
        assert set(s["table"]["variants"]) == set(deadends.QUICK_VARIANTS)


def lettered(figure) -> dict[str, str]:
    """The title of each lettered panel of ``figure``, by its letter (the letters drawn by plotting.style)."""
    out: dict[str, str] = {}
    for ax in figure.axes:
        for t in ax.texts:
            if t.get_gid() == LETTER_GID:
                assert t.get_text() not in out, f"letter {t.get_text()} twice"
                out[t.get_text()] = ax.get_title()
    return out


def test_the_panels_are_named_as_the_papers():
    for fig, long_panels in ((fig3, {"F": "cluttered", "G": "difficult"}), (fig5, {"F": "difficult (plastic)"})):
        res = run(fig, Settings(quick=True, seeds=1))
        assert list(res.summary["panels"]) == list("ABCDEFG")
        figure = fig.plot(res)
        titles = lettered(figure)
        assert set(titles) == set("ABCDEFG") | ({"H"} if fig is fig5 else set()), (fig.NAME, titles)
        assert "simple deadlock" in titles["A"] and "narrow passage" in titles["B"]
        assert "neural activations" in titles["C"] and "left" in titles["D"] and "right" in titles["E"]
        for letter, what in long_panels.items():
            assert what in titles[letter]
        texts = [t.get_text() for ax in figure.axes for t in ax.texts]
        assert not any("escaped / runs" in t for t in texts)  # the counts are a table now, not a block of text
        assert sum(len(ax.tables) for ax in figure.axes) == 1
    assert "weights" in titles["G"] and "difficult (plastic)" in titles["G"]  # Fig. 5G: the weights over the long run
    assert titles["H"] == "coverage (not in the paper)"


@pytest.mark.parametrize("weights_change", [True, False])
def test_panel_c_has_one_axes_per_signal_with_its_own_scale(weights_change):
    res = run(fig5, Settings(quick=True, seeds=1))
    if weights_change:  # the plastic network's weights grow; constant weights (the static network's) are not drawn
        n = len(res.arrays["narrow-passage/b"])
        res.arrays["narrow-passage/b"] = np.linspace(0, 3, 2 * n).reshape(n, 2)
    figure = fig5.plot(res)
    top = next(ax for ax in figure.axes if any(t.get_gid() == LETTER_GID and t.get_text() == "C" for t in ax.texts))
    c = [ax for ax in figure.axes if top.get_shared_x_axes().joined(ax, top)]
    assert [ax.get_ylabel() for ax in c] == ["input I", "output O", "weight"][: 3 if weights_change else 2]
    assert c[-1].get_xlabel() == "time (s)"
    for ax in c[:2]:
        assert [lab.get_text() for lab in ax.get_yticklabels()] == ["−1", "0", "1"]
    assert all(ax.get_legend() is not None for ax in c)


def test_fig5g_covers_the_whole_run():
    res = run(fig5, Settings(seeds=1))
    g = res.summary["fig5g"]
    step = res.arrays["difficult (plastic)/step"]
    assert g["first_step"] == step[0] == 0 and g["last_step"] == step[-1] == fig5.LONG_STEPS - 1
    assert g["stride"] == long_runs.LONG_STRIDE == 10 and set(np.diff(step)) <= {10, 9}
    assert g["rows"] == len(step) == fig5.LONG_STEPS // 10 + 1 and g["finite"]
    assert g["weights"] == ["b1", "b2", "c1", "c2"] and g["seconds"] == 10_000.0
    assert res.arrays["difficult (plastic)/b"].shape == (len(step), 2)


@pytest.fixture(scope="module")
def streamed():
    """A long run of 3,001 control steps in the difficult arena, streamed, and the same run held in memory."""
    from neurowalk.sim.episode import run_episode

    spec = {"arena": "difficult", "controller": "plastic", "steps": 3001}
    return run_kept((long_runs.LONG,), spec), run_episode(EpisodeConfig(**spec))


def test_a_streamed_long_run_keeps_every_tenth_row_and_the_summary_of_the_whole_run(streamed):
    stored, whole = streamed
    kept = stored["kept"]["long"]
    step = np.asarray(kept["step"])
    assert step[0] == 0 and step[-1] == 3000 and set(np.diff(step)) == {10}  # 3000 is a tenth step itself
    tr = whole.trajectory
    for k in long_runs.TRACES:
        assert np.array_equal(np.asarray(kept[k]), getattr(tr, k)[step]), k  # bit for bit the rows of the run
    assert np.isfinite(np.asarray(kept["b"])).all() and np.isfinite(np.asarray(kept["q"])).all()
    machine = ("wall_time_s", "real_time_factor")
    a = {k: v for k, v in stored.items() if k not in machine and k != "kept"}
    b = {k: v for k, v in result_of(whole).items() if k not in machine}
    assert a == b
    assert whole.summary["wedged_periods"] >= 1  # the contacts of a wedged period are replayed for its cause
    assert kept["coverage"][-1] == whole.summary["coverage"]
    assert bool(np.all(np.diff(kept["coverage"]) >= 0))


def test_first_visits_give_the_coverage_of_every_prefix():
    from neurowalk import metrics
    from neurowalk.arenas import make_arena

    arena = make_arena("difficult")
    rng = np.random.default_rng(3)
    walk = np.cumsum(rng.normal(0, 0.05, (2000, 2)), axis=0) + np.array([3.0, -1.0])
    pose = np.column_stack([walk, np.zeros(2000)])
    pose[100] = np.nan
    fv = long_runs.FirstVisits(arena)
    for start in range(0, 2000, 300):  # in chunks, as a streamed run hands them over
        fv.add(pose[start : start + 300], start)
    at = np.array([0, 99, 100, 101, 777, 1999])
    want = [metrics.coverage(pose[: s + 1], arena) for s in at]
    assert fv.curve(at).tolist() == pytest.approx(want, abs=0)


def test_sample_steps_keep_the_first_and_the_last():
    assert long_runs.sample_steps(25, 10).tolist() == [0, 10, 20, 24]
    assert long_runs.sample_steps(21, 10).tolist() == [0, 10, 20]
    assert long_runs.sample_steps(1, 10).tolist() == [0]


def test_many_wedged_periods_are_all_circled_and_only_the_longest_labelled():
    from matplotlib.patches import Circle

    from neurowalk.experiments.suites import deadends_plot
    from neurowalk.plotting.style import pyplot

    _, ax = pyplot().subplots()
    periods = [{"centre": [0.1 * k, 0.0], "extent_m": 0.2, "duration_s": 110.0 + k, "held": [[0, 1]],
                "held_s": 100.0 + k} for k in range(20)]  # fmt: skip
    deadends_plot.draw_wedged(ax, periods)
    assert sum(isinstance(p, Circle) for p in ax.patches) == 20
    labels = sorted(t.get_text() for t in ax.texts)
    most = deadends_plot.WEDGED_LABELS
    assert labels == sorted(f"{100 + k} s" for k in range(20 - most, 20))  # the longest, each once
    (entry,) = [line.get_label() for line in ax.get_lines()]
    assert entry == f"held 20x, {most} longest labelled (s)"
    _, ax = pyplot().subplots()
    deadends_plot.draw_wedged(ax, periods[:2])  # few: every one labelled, as before
    assert len(ax.texts) == 2 and ax.get_lines()[0].get_label() == "held (duration)"


def test_coinciding_coverage_curves_stay_visible_and_say_so():
    from neurowalk.experiments.suites import deadends_plot
    from neurowalk.plotting.style import pyplot

    _, ax = pyplot().subplots()
    step = np.arange(0, 1000, 10)
    a = {"p/step": step, "p/coverage": np.linspace(0, 0.2, 100)}
    a |= {"s/step": step, "s/coverage": np.minimum(step / 1e4, 0.015), "b/step": step}
    a["b/coverage"] = a["s/coverage"] + 0.001
    keys = ["difficult (plastic)", "difficult (static)", "difficult (braitenberg)"]
    a = {f"{k}/{part}": a[f"{k[11]}/{part}"] for k in keys for part in ("step", "coverage")}
    deadends_plot._coverage(ax, a, keys, 10.0)
    plastic, static, braitenberg = ax.get_lines()
    assert plastic.get_label() == "plastic" and static.get_label() == "static"
    assert braitenberg.get_label() == "braitenberg: on static's line\n(at most 0.1% apart)"
    assert static.get_linewidth() > braitenberg.get_linewidth()  # the lower one wider
    assert braitenberg.get_zorder() > static.get_zorder() and braitenberg.get_marker() == "o"
    assert plastic.get_marker() == "None" and static.get_marker() == "None"
    assert np.array_equal(braitenberg.get_ydata(), a["difficult (braitenberg)/coverage"])  # drawn as measured


def test_held_and_turning_periods_are_circled_apart_and_only_held_ones_labelled():
    from matplotlib.patches import Circle

    from neurowalk.experiments.suites import deadends_plot
    from neurowalk.plotting.style import pyplot

    _, ax = pyplot().subplots()
    held = {"centre": [0.0, 0.0], "extent_m": 0.2, "duration_s": 250.0, "held": [[0, 1799]], "held_s": 180.0}
    turning = {"centre": [3.0, 0.0], "extent_m": 0.2, "duration_s": 400.0, "held": [], "held_s": 0.0}
    deadends_plot.draw_wedged(ax, [held, turning])
    circles = [p for p in ax.patches if isinstance(p, Circle)]
    assert len(circles) == 2 and len({c.get_linestyle() for c in circles}) == 2  # drawn apart
    assert [t.get_text() for t in ax.texts] == ["180 s"]  # the held one, with the time held
    entries = [line.get_label() for line in ax.get_lines()]
    assert entries == ["held (duration)", "turning in place 1x (wedged, not held)"]


def test_the_saturating_fit_finds_where_a_curve_levels_off():
    t = np.linspace(0.0, 10_000.0, 101)
    fit = saturating_fit(t, 0.3 * (1.0 - np.exp(-t / 2500.0)))
    assert fit["c_max"] == pytest.approx(0.3, rel=0.02) and fit["tau_s"] == pytest.approx(2500.0, rel=0.03)
    assert fit["rms"] < 1e-3
    straight = saturating_fit(t, 2.4e-5 * t)  # a curve still rising straight: it levels off beyond its end
    assert straight["tau_s"] > 10_000.0 and straight["c_max"] > 0.24


def test_the_authors_coverage_curve_ends_at_their_runs_coverage():
    steps = np.arange(0, 100_000, 10_000)
    curve = authors.coverage_curve("plastic", np.append(steps, 99_999))
    assert np.all(np.diff(curve) >= 0) and curve[0] < 0.01
    assert curve[-1] == pytest.approx(authors.long_runs()["plastic"]["coverage"])


@pytest.mark.parametrize(
    ("coverage", "verdict"),
    [([0.24, 0.25, 0.26, 0.22], "reproduced"), ([0.18, 0.19, 0.19, 0.25], "partly"), ([0.10, 0.11, 0.12], "not")],
)
def test_fig5f_is_judged_against_the_authors_run_less_the_seeds_spread(coverage, verdict):
    sd = float(np.std(coverage, ddof=1))
    f = {"coverage": coverage, "median": float(np.median(coverage)), "sd": sd, "seconds": 10_000.0,
         "fits": [{"c_max": 0.3, "tau_s": 5000.0, "rms": 0.0}] * len(coverage), "rule": "r",
         "authors": {"coverage": 0.259, "fit": {"c_max": 25.2, "tau_s": 1e6, "rms": 0.0}}}  # fmt: skip
    c = fig5.explored_claim(f)
    assert c.verdict == verdict and "authors' 25.9%" in c.measured and "levels off at 30%, tau 5,000 s" in c.rule
    assert "The authors' run: 25.9% (still rising at the end" in c.rule  # a straight curve: no level claimed


def test_fig5_judges_its_exploration_over_seeds_beside_the_authors_run():
    runs = plan("fig5", Settings(quick=True))
    extra = [p for p in runs if p.label[0] == "coverage"]
    assert [p.config.seed for p in extra] == [1] and all(p.config.controller == "plastic" for p in extra)
    drawn = next(p for p in runs if p.label == ("long", "difficult (plastic)"))
    assert all(p.config.steps == drawn.config.steps and p.config.arena == "difficult" for p in extra)
    assert len([p for p in plan("fig5", Settings()) if p.label[0] == "coverage"]) == fig5.COVERAGE_SEEDS[0] - 1
