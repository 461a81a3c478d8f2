"""Make docs/notebooks/first_run.ipynb: a first run in Jupyter (a run, its picture, the weights, a small study),
its cells run in order by a real Jupyter kernel (nbclient), their printed lines and inline pictures stored as the
cells' outputs.

``tests/docs/test_notebook.py`` runs the committed notebook again in a Jupyter kernel in an empty folder and holds its
printed lines and pictures to the stored ones; the site shows it as a page (``mkdocs_hooks.py``).

Run: ``python tools/notebook.py`` (writes docs/notebooks/first_run.ipynb; a minute).
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path
from typing import Any

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


def execute(nb: dict[str, Any], folder: Path, timeout_s: int = 600) -> dict[str, Any]:
    """``nb`` (nbformat 4, as a dict) with every code cell run in order by a real Jupyter kernel (nbclient,
    ``python3``), in ``folder``: each cell's outputs as Jupyter makes them (printed text, inline pictures as
    ``image/png``, a last value's ``execute_result``, none where the cell ends in ``;``)."""
    import nbformat
    from nbclient import NotebookClient

    book = nbformat.from_dict(nb)
    NotebookClient(
        book, timeout=timeout_s, kernel_name="python3", resources={"metadata": {"path": str(folder)}}
    ).execute()
    return json.loads(nbformat.writes(book))


def pictures(nb: dict[str, Any]) -> list[int]:
    """How many ``image/png`` outputs each code cell of ``nb`` has."""
    return [
        sum("image/png" in o.get("data", {}) for o in c["outputs"]) for c in nb["cells"] if c["cell_type"] == "code"
    ]


def notebook(cells: list[tuple[str, str]]) -> dict[str, Any]:
    """The notebook (nbformat 4) of ``cells``, not yet run."""
    out = []
    for kind, source in cells:
        cell: dict[str, Any] = {"cell_type": kind, "metadata": {}, "source": source}
        if kind == "code":
            cell.update(execution_count=None, outputs=[])
        out.append(cell)
    meta = {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
            "language_info": {"name": "python"}}  # fmt: skip
    return {"cells": out, "metadata": meta, "nbformat": 4, "nbformat_minor": 5}


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        nb = execute(notebook(CELLS), Path(tmp))
    for cell in nb["cells"]:  # the kernel's timings, ids and progress bars (stderr) say nothing of the notebook
        cell.pop("id", None)
        cell["metadata"] = {}
        if cell["cell_type"] == "code":
            cell["outputs"] = [o for o in cell["outputs"] if o.get("name") != "stderr"]
    NOTEBOOK.parent.mkdir(parents=True, exist_ok=True)
    NOTEBOOK.write_text(json.dumps(nb, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {NOTEBOOK}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
