"""FIGURES is a table written out: every figure module is in it once, with a run and a plot, and importing the
table imports no figure."""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import subprocess
import sys

import neurowalk.experiments.figures
from neurowalk.experiments import FIGURES, FunctionAt


def test_every_figure_module_is_in_the_table_once_with_its_run_and_plot():
    modules = {m.name for m in pkgutil.iter_modules(neurowalk.experiments.figures.__path__)}
    named = [exp.run.module.rsplit(".", 1)[1] for exp in FIGURES.values()]  # type: ignore[attr-defined]
    assert sorted(named) == sorted(modules)
    for name, exp in FIGURES.items():
        assert exp.name == name and exp.title
        assert isinstance(exp.run, FunctionAt) and isinstance(exp.plot, FunctionAt)
        module = importlib.import_module(exp.run.module)
        assert exp.plot.module == exp.run.module
        assert exp.run.load() is module.run and exp.plot.load() is module.plot
        params = inspect.signature(exp.run).parameters  # the CLI reads the figure's own parameters
        assert {"quick", "seed"} <= set(params)
        assert getattr(module, "NAME", name) == name


def test_importing_the_table_imports_no_figure():
    code = (
        "import sys; from neurowalk.experiments import FIGURES; "
        "print(sorted(m for m in sys.modules if m.startswith('neurowalk.experiments.')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
