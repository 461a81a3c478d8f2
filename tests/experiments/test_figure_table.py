"""FIGURES is a table written out: every figure module is in it once, with a run and a plot and the settings its run
takes, and importing the table imports no figure."""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import subprocess
import sys

import neurowalk.experiments.figures
from neurowalk.experiments import FIGURES, FigureRun, FunctionAt
from neurowalk.experiments.study import OPTIONAL


def test_every_figure_module_is_in_the_table_once_with_its_run_and_plot():
    modules = {m.name for m in pkgutil.iter_modules(neurowalk.experiments.figures.__path__)}
    named = [exp.plot.module.rsplit(".", 1)[1] for exp in FIGURES.values()]  # type: ignore[attr-defined]
    assert sorted(named) == sorted(modules)
    for name, exp in FIGURES.items():
        assert exp.name == name and exp.title and isinstance(exp.plot, FunctionAt)
        module = importlib.import_module(exp.plot.module)
        assert exp.plot.load() is module.plot and getattr(module, "NAME", name) == name
        parts = (exp.compute,) if exp.compute is not None else (exp.runs, exp.measure)
        assert all(isinstance(p, FigureRun | FunctionAt) and p.module == exp.plot.module for p in parts), name


def test_each_figure_declares_exactly_the_settings_its_run_takes():
    """The registry's declaration (what the CLI offers) against the run's own keywords: none missing, none extra."""
    for name, exp in FIGURES.items():
        if not isinstance(exp.compute, FigureRun):
            continue  # a study of runs: the runner applies every setting it takes
        params = set(inspect.signature(importlib.import_module(exp.compute.module).run).parameters)
        assert {"quick", "seed"} <= params, name
        assert set(exp.takes) == params & set(OPTIONAL), name
        assert exp.keeps_runs == ("out" in params), name
        assert ("device" in params) == ("engine" in params), name


def test_importing_the_table_imports_no_figure():
    code = (
        "import sys; from neurowalk.experiments import FIGURES; "
        "print(sorted(m for m in sys.modules if m.startswith('neurowalk.experiments.')"
        " and m != 'neurowalk.experiments.study'))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
