"""FIGURES is a table written out: every figure module is in it once, with a run and a plot and the settings its run
takes, and importing the table imports no figure."""

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
    named = [exp.plot.module.rsplit(".", 1)[1] for exp in FIGURES.values()]  # type: ignore[attr-defined]
    assert sorted(named) == sorted(modules)
    for name, exp in FIGURES.items():
        assert exp.name == name and exp.title and isinstance(exp.plot, FunctionAt)
        module = importlib.import_module(exp.plot.module)
        assert exp.plot.load() is module.plot and getattr(module, "NAME", name) == name
        parts = (exp.compute,) if exp.compute is not None else (exp.runs, exp.measure)
        assert all(isinstance(p, FunctionAt) and p.module == exp.plot.module for p in parts), name


def _settings_read(module: str) -> set[str]:
    """The settings the module, and the suites it imports, read from a Settings (``s.X``; ``s.n(...)``: seeds)."""
    import ast

    mod = importlib.import_module(module)
    tree = ast.parse(inspect.getsource(mod))
    names = {a.attr for a in ast.walk(tree) if isinstance(a, ast.Attribute) and getattr(a.value, "id", "") == "s"}
    suites = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and "suites" in (n.module or "")}
    for suite in suites - {module}:
        names |= _settings_read(suite)
    return names | ({"seeds"} if "n" in names else set())


def test_each_figure_reads_every_setting_it_declares():
    """A setting a figure offers on the command line is one its code reads (engine: with its device)."""
    for name, exp in FIGURES.items():
        read = _settings_read(exp.plot.module)  # type: ignore[attr-defined]
        missing = set(exp.takes) - read
        assert not missing, f"{name} declares {sorted(missing)} but never reads them"
        assert ("engine" in exp.takes) <= ("device" in read), name


def test_importing_the_table_imports_no_figure():
    code = (
        "import sys; from neurowalk.experiments import FIGURES; "
        "print(sorted(m for m in sys.modules if m.startswith('neurowalk.experiments.')"
        " and m != 'neurowalk.experiments.study'))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
