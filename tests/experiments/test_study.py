"""Studies: the settings, the declaration, the runner (store, resume, files) and a study read from a user's file."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from neurowalk import EpisodeConfig, Plan, Settings, Study, run_study
from neurowalk.experiments.study import OPTIONAL, compute
from neurowalk.experiments.study_check import load_study
from neurowalk.runners.store import ResultStore

BASE = EpisodeConfig(arena="simple-deadlock", body="surrogate", steps=300)


def _runs(s: Settings):
    for controller in ("static", "plastic"):
        for i in range(s.n(full=3, quick=2)):
            yield Plan(controller, BASE.replace(controller=controller, seed=s.seed + i))


def _measure(s: Settings, results):
    return {name: [r.path_length_m for r in runs] for name, runs in results.items()}


def _plot(result):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot(result.summary["plastic"])
    return fig


TINY = Study("tiny", "path lengths", plot=_plot, runs=_runs, measure=_measure)


def test_settings_check_their_values_and_say_what_is_given():
    for bad, word in (({"seed": -1}, "seed"), ({"seeds": 0}, "seeds"), ({"control_hz": float("nan")}, "control_hz"),
                      ({"workers": 0}, "workers"), ({"backend": "spark"}, "backend")):  # fmt: skip
        with pytest.raises(ValueError, match=word):
            Settings(**bad)
    assert Settings().given() == [] and Settings(quick=True, seed=3).given() == []
    assert Settings(device="cpu", address="a:1", climbing=True).given() == ["climbing", "engine", "backend"]
    assert Settings().n(10) == 10 and Settings(quick=True).n(10, 3) == 3 and Settings(seeds=7, quick=True).n(10) == 7
    s = Settings(params={"mu_b": 0.01})
    with pytest.raises(TypeError):
        s.params["mu_b"] = 1.0  # type: ignore[index]
    hash(s)


def test_settings_apply_the_run_settings_given_and_nothing_else():
    cfg = EpisodeConfig(arena="corner", body="amosii", steps=50)
    assert Settings(quick=True, seeds=4, workers=3).apply(cfg) is cfg
    done = Settings(control_hz=20.0, variant="original", climbing=True, gait="tripod").apply(cfg)
    assert (done.control_hz, done.variant, done.reflexes, done.backbone, done.gait) == (20.0, "original", True, True,
                                                                                      "tripod")  # fmt: skip
    assert done.replace(control_hz=10.0, variant="paper", reflexes=False, backbone=False, gait="wave") == cfg


def test_a_study_declares_what_it_takes_and_refuses_the_rest():
    assert TINY.takes == ("seeds", "workers", "backend")
    with pytest.raises(ValueError, match=r"takes no gait, video; it takes: seeds, workers, backend"):
        TINY.check(Settings(video=True, gait="tripod"))
    with pytest.raises(ValueError, match="unknown settings"):
        Study("x", "x", plot=_plot, runs=_runs, measure=_measure, takes=("seeds", "colour"))
    with pytest.raises(TypeError, match="measure"):
        Study("x", "x", plot=_plot, runs=_runs)  # type: ignore[call-arg]
    with pytest.raises(ValueError, match="study 'x' needs measure"):
        Study("x", "x", plot=_plot, runs=_runs, measure=None)  # type: ignore[arg-type]


def test_runs_yield_typed_plans_and_measure_gets_each_run_with_its_plan(tmp_path: Path):
    """A bare tuple is refused naming the study; measure sees the config each run ran (the settings applied)."""
    bare = Study("bare", "x", plot=_plot, runs=lambda s: iter([("a", BASE)]), measure=_measure)
    with pytest.raises(TypeError, match="study 'bare': runs must yield Plan"):
        compute(bare, Settings(out=tmp_path / "bare"))
    seen = {}

    def measure(s, results):
        seen.update({label: [r.config for r in rs] for label, rs in results.items()})
        return {}

    study = Study("typed", "x", plot=_plot, runs=_runs, measure=measure, takes=("seeds", "control_hz", "workers"))
    compute(study, Settings(seeds=2, seed=5, workers=1, out=tmp_path / "typed"))
    assert {label: [c.seed for c in cs] for label, cs in seen.items()} == {"static": [5, 6], "plastic": [5, 6]}
    assert all(c.controller == label for label, cs in seen.items() for c in cs)
    with pytest.raises(ValueError, match="fixes only run settings"):
        Plan("a", BASE, fixed=("seeds",))
    assert set(OPTIONAL) >= {"seeds", "body", "control_hz", "workers", "backend"}


def test_run_study_writes_its_files_and_resumes_from_its_store(tmp_path: Path):
    s = Settings(quick=True, out=tmp_path, workers=1)
    result, paths = run_study(TINY, s)
    assert set(paths) == {"png", "json"} and all(p.is_file() for p in paths.values())
    assert list(result.summary) == ["static", "plastic"]  # what its measure returned, nothing added
    assert all(len(result.summary[k]) == 2 for k in ("static", "plastic"))
    code = result.code  # of the package and this file (the study's)
    assert json.loads(paths["json"].read_text()) == {**result.summary, "quick": True, "code": code} and len(code) == 16
    with ResultStore(tmp_path / "results.sqlite", code) as store:
        first = {row["key"]: row["finished_at"] for row in store.rows()}
    assert len(first) == 4
    again = compute(TINY, s.replace(seeds=3))  # one more seed: only its two runs run
    with ResultStore(tmp_path / "results.sqlite", code) as store:
        rows = {row["key"]: row["finished_at"] for row in store.rows()}
    assert len(rows) == 6 and all(rows[k] == t for k, t in first.items())
    assert [again.summary[k][:2] for k in ("static", "plastic")] == [result.summary[k] for k in ("static", "plastic")]


def test_the_runs_get_the_settings_and_the_study_sees_typed_summaries(tmp_path: Path):
    seen = {}

    def measure(s, results):
        seen.update(results)
        return {"n": sum(len(v) for v in results.values())}

    study = Study("t", "t", plot=_plot, runs=_runs, measure=measure, takes=("seeds", "control_hz", "workers"))
    compute(study, Settings(quick=True, seeds=1, out=tmp_path, control_hz=10.0, workers=1))
    (static,) = seen["static"]
    assert static.controller == "static" and static.body == "surrogate" and static.steps == 300
    assert isinstance(static.escaped, bool) and static.control_hz == 10.0


def test_a_study_file_is_read_by_its_variable_or_its_only_study(tmp_path: Path):
    text = (
        "from neurowalk import EpisodeConfig, Plan, Study\n"
        "def runs(s):\n    yield Plan('a', EpisodeConfig(body='surrogate', steps=20))\n"
        "{name} = Study('f', 'f', plot=print, runs=runs, measure=lambda s, r: {{}})\n"
    )
    for name in ("study", "mine"):
        (tmp_path / f"{name}.py").write_text(text.format(name=name))
        assert load_study(tmp_path / f"{name}.py").name == "f"
    (tmp_path / "two.py").write_text(text.format(name="a") + text.format(name="b").split("\n", 3)[-1])
    with pytest.raises(ValueError, match="defines 2 studies"):
        load_study(tmp_path / "two.py")
    with pytest.raises(ValueError, match="no study file"):
        load_study(tmp_path / "none.py")


def test_the_help_of_a_study_and_of_a_figure_lists_exactly_the_settings_each_takes(tmp_path: Path, capsys):
    from neurowalk.cli import main
    from neurowalk.cli.settings import FLAGS
    from neurowalk.experiments import FIGURES

    every = {f for flags in FLAGS.values() for f in flags.split()[0].split("/")}
    (tmp_path / "s.py").write_text(
        "from neurowalk import Study\n"
        "study = Study('s', 's', plot=print, runs=print, measure=print, takes=('seeds', 'control_hz'))\n"
    )
    for argv, takes in ((["study", str(tmp_path / "s.py")], ("seeds", "control_hz")),
                        *((["figure", name], exp.takes) for name, exp in FIGURES.items())):  # fmt: skip
        with pytest.raises(SystemExit):
            main([*argv, "--help"])
        text = capsys.readouterr().out.split("figures:")[0] + " "
        shown = {f for f in every if f"{f} " in text}
        assert shown == {f for n in takes for f in FLAGS[n].split()[0].split("/")}, argv


def test_a_run_summary_reads_a_summary_by_attribute_and_gives_it_back(tmp_path: Path):
    from neurowalk import RunSummary, run_episode
    from neurowalk.fileio import to_jsonable

    ep = run_episode(BASE.replace(controller="static"))
    d = json.loads(json.dumps(to_jsonable(ep.summary)))
    r = RunSummary.from_dict(d)
    assert ep.result.to_dict() == ep.summary and ep.result.trapped is ep.summary["trapped"]
    assert r.to_dict() == d and r.controller == "static" and r.escaped is d["escaped"]
    assert r.exit_s == (None if d["exit_step"] is None else d["exit_step"] / 10.0)
    assert hash(r.final_pose) is not None and isinstance(r.wedged, tuple)
    older = {k: v for k, v in d.items() if k not in ("gait", "body_opts", "ever_held_up_1000s")}
    assert RunSummary.from_dict(older).ever_held_up_1000s is None
    with pytest.raises(ValueError, match="no steps"):
        RunSummary.from_dict({k: v for k, v in d.items() if k != "steps"})
    with pytest.raises(AttributeError):
        r.escaped = True  # type: ignore[misc]


def test_a_resumed_study_counts_only_the_kept_runs_its_own_settings_need(tmp_path: Path):
    from neurowalk.experiments.study import kept_runs

    run_study(TINY, Settings(quick=True, out=tmp_path, workers=1))  # 4 runs kept, seeds 0 and 1
    assert kept_runs(TINY, Settings(quick=True, out=tmp_path)) == {tmp_path / "results.sqlite": 4}
    assert kept_runs(TINY, Settings(quick=True, seed=1, out=tmp_path)) == {tmp_path / "results.sqlite": 2}
    assert kept_runs(TINY, Settings(quick=True, seed=7, out=tmp_path)) == {}  # other settings: nothing to go on from


def test_a_figure_inside_shared_stores_counts_the_runs_kept_there(tmp_path: Path):
    from neurowalk.experiments import FIGURES
    from neurowalk.experiments.command import interrupted_line
    from neurowalk.experiments.study import kept_runs, planned
    from neurowalk.experiments.study_runs import run_store

    figure, s = FIGURES["table2"], Settings(quick=True, seeds=1, out=tmp_path / "table2")
    plan, *_ = planned(figure, s)
    first, terms = plan.config, plan.terms
    run_store([(first, terms), (first.replace(seed=99), ())], tmp_path / "runs", 1)  # one of its runs, one not
    kept = kept_runs(figure, s.replace(shared_runs=tmp_path / "runs"))
    assert kept == {tmp_path / "runs" / "results.sqlite": 1}  # only the runs its own settings need
    assert f"1 finished runs are kept in {tmp_path / 'runs'}" in interrupted_line("table2", kept)
    assert kept_runs(figure, s) == {}  # without them: its own folder holds none


def test_a_study_whose_own_measure_raises_shows_its_own_frames_and_what_is_kept(tmp_path: Path, capsys):
    from neurowalk.cli import main

    (tmp_path / "bad.py").write_text(
        "from neurowalk import EpisodeConfig, Plan, Study\n"
        "def runs(s):\n"
        "    for seed in range(3):\n"
        "        yield Plan('a', EpisodeConfig(body='surrogate', steps=20, seed=seed))\n"
        "def measure(s, results):\n"
        "    return {'x': 1 / 0}\n"
        "study = Study('bad', 'bad', plot=print, runs=runs, measure=measure)\n"
    )
    assert main(["study", str(tmp_path / "bad.py"), "--out", str(tmp_path / "out"), "--workers", "1"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    err = err[next(i for i, line in enumerate(err) if line.startswith("Traceback")) :]  # after the progress bar
    assert err[0] == "Traceback (the study file's own frames):"
    assert any("bad.py" in line and "line 6, in measure" in line for line in err)
    assert not any("neurowalk" in line and "File" in line for line in err)  # none of neurowalk's frames
    assert err[-2] == "ZeroDivisionError: division by zero"
    assert err[-1].startswith("neurowalk: study bad failed in ") and "3 finished runs are kept in" in err[-1]


def test_a_grid_declares_every_combination_for_every_seed_labelled_by_its_values():
    from neurowalk.experiments.study import grid

    base = EpisodeConfig(arena="narrow-passage", body="surrogate", steps=50)
    s = Settings(seed=3, seeds=2)
    runs = list(grid(base, s.seed_range(10), controller=["static", "plastic"], **{"arena_opts.gap": [0.2, 0.3]}))
    assert [p.label for p in runs[::2]] == [("static", 0.2), ("static", 0.3), ("plastic", 0.2), ("plastic", 0.3)]
    assert [p.config.seed for p in runs] == [3, 4] * 4 and len({p.config.key() for p in runs}) == 8
    assert all(p.config.controller == p.label[0] and p.config.arena_opts["gap"] == p.label[1] for p in runs)
    assert Settings(quick=True).seed_range(10, 3) == range(0, 3)


def test_a_figures_json_records_each_physics_its_runs_stepped(tmp_path: Path):
    """A study's json says the physics of its runs as they ran (the step fitted to the control rate), each distinct
    one once: two runs of one physics give one record, a run given another integrator a second."""
    walk = EpisodeConfig(arena="open", steps=2)

    def runs(s: Settings):
        yield Plan("a", walk.replace(seed=0))
        yield Plan("a", walk.replace(seed=1))
        yield Plan("b", walk.replace(body_opts={"integrator": "implicitfast"}, control_hz=27.0))

    study = Study("phys", "physics", plot=_plot, runs=runs, measure=lambda s, r: {"n": len(r)}, records_physics=True)
    physics = compute(study, Settings(out=tmp_path, workers=1)).summary["physics_settings"]
    assert [(p["body"], p["control_hz"], p["integrator"], p["substeps"]) for p in physics] == [
        ("amosii", 10.0, "discrete", 10),
        ("amosii", 27.0, "implicitfast", 4),
    ]
    assert physics[1]["timestep_s"] == pytest.approx(1 / 108)


def test_a_run_stored_with_another_physics_runs_again(tmp_path: Path):
    """A store of an older neurowalk holds its runs under the keys today's configs have (a key names the options
    given, not the defaults); a run whose stored physics is not the physics it steps today runs again, the others
    are taken as they are."""
    walk = EpisodeConfig(arena="open", steps=3)

    def runs(s: Settings):
        yield Plan("a", walk.replace(seed=0))
        yield Plan("a", walk.replace(seed=1))

    study = Study("older", "physics", plot=_plot, runs=runs, measure=lambda s, r: {"x": [k.final_pose for k in r["a"]]})
    s = Settings(out=tmp_path, workers=1)
    first = compute(study, s)
    with ResultStore(tmp_path / "results.sqlite", first.code) as store:
        rows = {r["key"]: r for r in store.rows()}
        older = walk.replace(seed=0).key()
        former = {
            **rows[older]["result"],
            "physics": {**rows[older]["result"]["physics"], "integrator": "implicitfast"},
        }
        store.put(older, rows[older]["spec"], result=former)
        before = {k: store.rows(keys=[k])[0]["finished_at"] for k in rows}
    again = compute(study, s)
    with ResultStore(tmp_path / "results.sqlite", first.code) as store:
        after = {k: store.rows(keys=[k])[0]["finished_at"] for k in rows}
        assert store.results(keys=[older])[older]["physics"]["integrator"] == "discrete"
    assert after[older] != before[older] and all(after[k] == before[k] for k in rows if k != older)
    assert again.summary == first.summary


@pytest.mark.parametrize(
    "body,says",
    [
        ("x = undefined_name + 1\n", "bad.py, line 2 (`x = undefined_name + 1`): NameError: name 'undefined_name'"),
        ("x = = 1\n", "bad.py, line 2: SyntaxError: invalid syntax (`x = = 1`)"),
        ("import no_such_module_here\n", "bad.py, line 2 (`import no_such_module_here`): ModuleNotFoundError"),
        (
            "def runs(s):\n    yield 'a', EpisodeConfig(body='surrogate', steps=20)\n"
            "study = Study('t', 't', plot=print, runs=runs, measure=lambda s, r: {})\n",
            "study 't': run 0 of runs(settings) is a tuple, not a Plan (write `yield Plan(label, config)`)",
        ),
        (
            "def runs(s):\n    yield Plan('a', EpisodeConfig(body='surrogate', steps=20))\n"
            "study = Study('t', 't', plot=print, runs=runs, measure=lambda s: {})\n",
            "study 't': measure must take 2 argument(s) (settings, runs)",
        ),
        (
            "def runs(s):\n    yield Plan(['a'], EpisodeConfig(body='surrogate', steps=20))\n"
            "study = Study('t', 't', plot=print, runs=runs, measure=lambda s, r: {})\n",
            "study 't': run 0 of runs(settings): its label ['a'] is not hashable",
        ),
    ],
    ids=["name", "syntax", "import", "tuple", "arity", "label"],
)
def test_a_study_file_with_an_error_is_refused_in_one_line_before_anything_runs(tmp_path: Path, body, says):
    """`neurowalk study` checks the file (check_study) first: one line naming the file's line and the error, exit 2,
    no traceback, no output folder."""
    import subprocess
    import sys

    (tmp_path / "bad.py").write_text("from neurowalk import EpisodeConfig, Plan, Study\n" + body)
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-m", "neurowalk", "study", "bad.py", "--out", str(out)], cwd=tmp_path,
                         capture_output=True, text=True)  # fmt: skip
    assert run.returncode == 2, run.stderr
    assert run.stderr.strip().splitlines() == [run.stderr.strip()] and says in run.stderr, run.stderr
    assert not out.exists()
