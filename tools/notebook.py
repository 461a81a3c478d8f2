"""Make docs/notebooks/first_run.ipynb: a first run in Jupyter (a run, its picture, the weights, a small study),
its cells run here in order as Jupyter runs them, their printed lines and pictures stored as the cells' outputs.

``tests/docs/test_notebook.py`` runs the committed notebook's cells again in an empty folder and holds their printed
lines to the stored ones; the site shows it as a page (``mkdocs_hooks.py``).

Run: ``python tools/notebook.py`` (writes docs/notebooks/first_run.ipynb; a minute).
"""

from __future__ import annotations

import ast
import base64
import contextlib
import io
import json
import os
import sys
import tempfile
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOK = ROOT / "docs" / "notebooks" / "first_run.ipynb"

CELLS: list[tuple[str, str]] = [
    (
        "markdown",
        """# A first run, in a notebook

The simulated AMOSII walks towards a box with the plastic network in the loop: the right ultrasonic sensor sees the
box first, the right neuron switches on, its self-connection and the shared inhibition grow, and the robot turns
left around the box. Run the cells in order, in Jupyter, after `pip install -e .` in neurowalk's folder (the first
run also compiles the simulation's kernels, once: some seconds).""",
    ),
    (
        "code",
        """from neurowalk import EpisodeConfig, plot_run, run_episode

ep = run_episode(EpisodeConfig(arena="box", controller="plastic", steps=1500))
s = ep.summary
print(
    f"{s['steps']} steps, {s['steps'] / s['control_hz']:.0f} s simulated: ended {s['net_displacement_m']:.2f} m "
    f"from its start, turned {s['heading_change_deg']:+.0f} deg"
)""",
    ),
    (
        "markdown",
        """Its picture, as `neurowalk run` draws it into `run.png`: the path from above, coloured by time; the
inputs of the two neurons, their outputs (the steering) and their weights over time.""",
    ),
    ("code", "plot_run(ep);"),
    (
        "markdown",
        """The weights themselves: each neuron's self-connection `b` and the shared inhibition `c`, every
control step in `ep.trajectory` (arrays, one row per step).""",
    ),
    (
        "code",
        """import matplotlib.pyplot as plt

tr = ep.trajectory
fig, ax = plt.subplots(figsize=(8, 3), layout="constrained")
ax.plot(tr.t, tr.b[:, 0], label="b1 (left)")
ax.plot(tr.t, tr.b[:, 1], label="b2 (right)")
ax.plot(tr.t, -0.5 * tr.q.sum(axis=1), "k--", label="c = -(q1 + q2)/2")
ax.set(xlabel="time (s)", ylabel="weight")
ax.legend()
print(f"final b = {[round(float(b), 3) for b in tr.b[-1]]}, c = {-0.5 * float(tr.q[-1].sum()):.3f}")""",
    ),
    (
        "markdown",
        """A small study: both networks in the narrow passage, four seeds each, on the planar surrogate
(a few seconds). A study declares its runs, what it measures of them and its picture; `run_study` runs them through the
result store of its folder, so that running the cell again takes them from there
([your own experiment](../tutorials/study.md) says more).""",
    ),
    (
        "code",
        """from neurowalk import Plan, Settings, Study, run_study


def runs(s):
    for controller in ("static", "plastic"):
        for seed in s.seed_range(full=4):
            cfg = EpisodeConfig(arena="narrow-passage", controller=controller, body="surrogate", steps=10000, seed=seed)
            yield Plan(controller, cfg)


def measure(s, runs):
    return {controller: sum(r.escaped for r in kept) for controller, kept in runs.items()}


def plot(result):
    fig, ax = plt.subplots(figsize=(4, 3), layout="constrained")
    ax.bar(list(result.summary), list(result.summary.values()))
    ax.set(ylabel="escaped (runs of 4)", title="the narrow passage")
    return fig


study = Study("escapes", "escapes from the narrow passage", plot=plot, runs=runs, measure=measure)
result, files = run_study(study, Settings(out="out/escapes", workers=1))
print(f"{result.summary}; wrote {', '.join(map(str, files.values()))}")
plt.close("all")  # the picture run_study drew for its file; here, again:
plot(result);""",
    ),
]


def run_cells(cells: list[tuple[str, str]], folder: Path) -> list[list[dict[str, Any]]]:
    """Run the code cells in order in one namespace, in ``folder``, as Jupyter does with its inline pictures; each
    cell's outputs: its printed text, then the figures it left open (drawn at the cell's end), then its last
    expression's value (none where the cell ends in ``;``, as in Jupyter)."""
    from matplotlib.figure import Figure

    namespace: dict[str, Any] = {}
    outputs = []
    here = Path.cwd()
    os.chdir(folder)
    try:
        for kind, source in cells:
            if kind != "code":
                outputs.append([])
                continue
            tree = ast.parse(source)
            last = tree.body.pop() if tree.body and isinstance(tree.body[-1], ast.Expr) else None
            printed = io.StringIO()
            with contextlib.redirect_stdout(printed):
                exec(compile(tree, "<cell>", "exec"), namespace)
                value = eval(compile(ast.Expression(last.value), "<cell>", "eval"), namespace) if last else None
            if source.rstrip().endswith(";"):
                value = None
            out: list[dict[str, Any]] = []
            if printed.getvalue():
                out.append({"output_type": "stream", "name": "stdout", "text": printed.getvalue().splitlines(True)})
            figures = [plt.figure(n) for n in plt.get_fignums()]
            if isinstance(value, Figure) and value not in figures:
                figures.append(value)
            for fig in figures:
                png = io.BytesIO()
                fig.savefig(png, format="png", dpi=80)
                data = {"image/png": base64.b64encode(png.getvalue()).decode(), "text/plain": [repr(fig)]}
                out.append({"output_type": "display_data", "data": data, "metadata": {}})
            if value is not None and not isinstance(value, Figure):
                out.append({"output_type": "execute_result", "data": {"text/plain": [repr(value)]}, "metadata": {},
                            "execution_count": None})  # fmt: skip
            outputs.append(out)
            plt.close("all")
    finally:
        os.chdir(here)
    return outputs


def notebook(cells: list[tuple[str, str]], outputs: list[list[dict[str, Any]]]) -> dict[str, Any]:
    """The notebook (nbformat 4) of ``cells`` with their ``outputs``."""
    out = []
    count = 0
    for (kind, source), produced in zip(cells, outputs, strict=True):
        cell: dict[str, Any] = {"cell_type": kind, "metadata": {}, "source": source.splitlines(True)}
        if kind == "code":
            count += 1
            cell.update(execution_count=count, outputs=[{**o, "execution_count": count} if o["output_type"] ==
                                                        "execute_result" else o for o in produced])  # fmt: skip
        out.append(cell)
    meta = {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
            "language_info": {"name": "python"}}  # fmt: skip
    return {"cells": out, "metadata": meta, "nbformat": 4, "nbformat_minor": 5}


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        outputs = run_cells(CELLS, Path(tmp))
    NOTEBOOK.parent.mkdir(parents=True, exist_ok=True)
    NOTEBOOK.write_text(json.dumps(notebook(CELLS, outputs), indent=1) + "\n", encoding="utf-8")
    print(f"wrote {NOTEBOOK}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
