"""The first-run notebook (docs/notebooks/first_run.ipynb) runs: its code cells again, in order, in an empty folder,
print what it shows they print and draw as many pictures; the site shows it as a page."""

from __future__ import annotations

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from notebook import CELLS, NOTEBOOK, run_cells  # noqa: E402


def _cells() -> list[dict]:
    return json.loads(NOTEBOOK.read_text(encoding="utf-8"))["cells"]


def test_the_notebook_is_what_its_maker_writes():
    assert [(c["cell_type"], "".join(c["source"])) for c in _cells()] == CELLS, "run: python tools/notebook.py"


def test_its_cells_run_in_order_and_give_what_it_shows(tmp_path: Path):
    cells = _cells()
    again = run_cells([(c["cell_type"], "".join(c["source"])) for c in cells], tmp_path)
    for cell, outputs in zip(cells, again, strict=True):
        if cell["cell_type"] != "code":
            continue
        stored = cell["outputs"]
        assert [o["output_type"] for o in outputs] == [o["output_type"] for o in stored], "".join(cell["source"])
        for new, old in zip(outputs, stored, strict=True):
            if new["output_type"] == "stream":
                assert new["text"] == old["text"]  # the same run, the same numbers
    assert (tmp_path / "out" / "escapes" / "escapes.png").is_file()  # the study wrote its files
    pictures = [o for c in cells if c["cell_type"] == "code" for o in c["outputs"] if "image/png" in o.get("data", {})]
    assert len(pictures) == 3  # the run, its weights, the study


def test_the_site_shows_it_as_a_page_with_its_outputs(monkeypatch):
    import pytest

    pytest.importorskip("mkdocs")  # the docs extra
    monkeypatch.syspath_prepend(str(ROOT))
    import mkdocs_hooks

    page = mkdocs_hooks.notebook_page("first_run.ipynb", json.loads(NOTEBOOK.read_text(encoding="utf-8")))
    assert page.startswith("# A first run, in a notebook") and "[Download the notebook](first_run.ipynb)" in page
    assert page.count("```python") == sum(c["cell_type"] == "code" for c in _cells())
    assert page.count("](data:image/png;base64,") == 3 and "final b = " in page
