"""FIGURES is a table written out: every figure module is in it once, with its runs, measure and plot (or its own
loop) and the settings it takes, each of which reaches its runs; importing the table imports no figure."""

from __future__ import annotations

import importlib
import pkgutil
import subprocess
import sys

import neurowalk.experiments.figures
from fake_runs import plan
from neurowalk.experiments import FIGURES, FunctionAt, Settings


def test_every_figure_module_is_in_the_table_once_with_its_run_and_plot():
    modules = {m.name for m in pkgutil.iter_modules(neurowalk.experiments.figures.__path__)}
    named = [exp.plot.module.rsplit(".", 1)[1] for exp in FIGURES.values()]  # type: ignore[attr-defined]
    assert sorted(named) == sorted(modules)
    for name, exp in FIGURES.items():
        assert exp.name == name and exp.title and isinstance(exp.plot, FunctionAt)
        module = importlib.import_module(exp.plot.module)
        assert exp.plot.load() is module.plot and getattr(module, "NAME", name) == name
        parts = (exp.runs, exp.measure, *(p for p in (exp.render, exp.videos) if p is not None))
        assert all(isinstance(p, FunctionAt) and p.module == exp.plot.module for p in parts), name


#: Values away from the default of each setting, one of which changes what a study runs.
GIVEN = {"seeds": [4], "body": ["amosii"], "climbing": [True], "variant": ["original", "paper"],
         "params": [{"mu_b": 0.02}], "gait": ["tripod"], "size": [0.7], "engine": ["warp"],
         "control_hz": [20.0]}  # fmt: skip
EXECUTION = {"workers", "backend", "video"}  # how the runs run, or what else is written: not what is run


def test_each_setting_a_study_takes_changes_the_runs_it_asks_for():
    """A setting a study offers on the command line reaches its runs (the runner applies it, or the study reads
    it): the configs it asks for with the setting given differ from those without."""
    for name, study in FIGURES.items():
        if not plan(name, Settings(quick=True)):
            assert not set(study.takes) - EXECUTION, name  # a study of no run takes none of the run settings
            continue
        for setting in set(study.takes) - EXECUTION:
            base = {"body": "amosii"} if "body" in study.takes and setting in ("control_hz", "engine") else {}
            if setting == "variant" and "params" in study.takes:  # the variant params apply over (Table 2: its row)
                base = {"params": GIVEN["params"][0]}
            before = [p.config.key() for p in plan(name, Settings(quick=True, **base))]
            afters = [[p.config.key() for p in plan(name, Settings(quick=True, **base, **{setting: v}))]
                      for v in GIVEN[setting]]  # fmt: skip
            assert any(before != after for after in afters), f"{name}: {setting} changes none of its runs"


def test_importing_the_table_imports_no_figure():
    code = (
        "import sys; from neurowalk.experiments import FIGURES; "
        "print(sorted(m for m in sys.modules if m.startswith('neurowalk.experiments.')"
        " and m not in ('neurowalk.experiments.study', 'neurowalk.experiments.plan')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
