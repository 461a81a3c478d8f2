"""Every notebook in docs/ runs in Jupyter: executed by a real kernel (``jupyter nbconvert --execute``, nbclient) in
an empty folder, its cells print what it shows they print and draw its pictures inline (``image/png``), as many in
each cell as the committed notebook has; the site shows it as a page."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from notebook import CELLS, NOTEBOOK, pictures  # noqa: E402

NOTEBOOKS = sorted((ROOT / "docs").rglob("*.ipynb"))


def _cells() -> list[dict]:
    return json.loads(NOTEBOOK.read_text(encoding="utf-8"))["cells"]


def test_the_notebook_is_what_its_maker_writes():
    assert [(c["cell_type"], "".join(c["source"])) for c in _cells()] == CELLS, "run: python tools/notebook.py"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_it_runs_in_a_jupyter_kernel_and_gives_what_it_shows(path: Path, tmp_path: Path):
    """``jupyter nbconvert --to notebook --execute``, as a user runs it, in an empty folder: the same printed lines
    and the same pictures in each cell (Jupyter's inline backend shows them: neurowalk leaves it in place)."""
    run = tmp_path / path.name
    run.write_bytes(path.read_bytes())
    jupyter = Path(sys.executable).with_name("jupyter")
    env = {**os.environ, "NEUROWALK_COMPILE_NOTE": "0"}
    done = subprocess.run([str(jupyter), "nbconvert", "--to", "notebook", "--execute", "--output", "ran.ipynb",
                           str(run)], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=900)  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    stored = json.loads(path.read_text(encoding="utf-8"))
    ran = json.loads((tmp_path / "ran.ipynb").read_text(encoding="utf-8"))
    assert pictures(ran) == pictures(stored) and sum(pictures(ran)) > 0
    for old, new in zip(stored["cells"], ran["cells"], strict=True):
        if old["cell_type"] != "code":
            continue
        assert "error" not in [o["output_type"] for o in new["outputs"]], "".join(old["source"])
        assert _printed(new) == _printed(old)  # the same run, the same numbers (stderr: progress bars, timed)


def _printed(cell: dict) -> str:
    """What a cell printed on stdout, and its value's text."""
    out = [o for o in cell["outputs"] if o.get("name") == "stdout" or o["output_type"] == "execute_result"]
    return "".join("".join(o["text"]) if "text" in o else "".join(o["data"]["text/plain"]) for o in out)


def test_the_first_run_notebook_has_its_three_pictures_and_its_study_files():
    assert pictures(json.loads(NOTEBOOK.read_text(encoding="utf-8"))) == [0, 1, 1, 1]  # the run, its weights, the study


def test_the_site_shows_it_as_a_page_with_its_outputs(monkeypatch):
    import pytest

    pytest.importorskip("mkdocs")  # the docs extra
    monkeypatch.syspath_prepend(str(ROOT))
    import mkdocs_hooks

    page = mkdocs_hooks.notebook_page("first_run.ipynb", json.loads(NOTEBOOK.read_text(encoding="utf-8")))
    assert page.startswith("# A first run, in a notebook") and "[Download the notebook](first_run.ipynb)" in page
    assert page.count("```python") == sum(c["cell_type"] == "code" for c in _cells())
    assert page.count("](data:image/png;base64,") == 3 and "final b = " in page
