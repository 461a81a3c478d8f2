"""The tutorial "Your own experiment": its study file, run again, gives the committed picture's numbers exactly, and
its quick mode shows the same behaviour (runs long enough to get out of the passage)."""

from __future__ import annotations

import json
from pathlib import Path

from doc_blocks import ROOT, blocks

from neurowalk import Settings, load_study, run_study

PAGE = "docs/tutorials/study.md"
COMMITTED = ROOT / "docs/studies/gap/gap.json"


def _gap_py(folder: Path) -> Path:
    """The page's study file, saved as the reader saves it."""
    (block,) = [b for b in blocks(PAGE) if b.kind == "file"]
    assert block.why == "gap.py" and len(block.code.splitlines()) <= 30  # the "at most 30 lines"
    (folder / "gap.py").write_text(block.code)
    return folder / "gap.py"


def test_the_tutorial_study_gives_the_committed_numbers(tmp_path: Path) -> None:
    result, files = run_study(load_study(_gap_py(tmp_path)), Settings(out=tmp_path / "out"))
    assert result.summary == json.loads(COMMITTED.read_text())
    assert {p.name for p in files.values()} == {"gap.png", "gap.json"}


def test_the_tutorial_study_escapes_in_quick_mode(tmp_path: Path) -> None:
    """`--quick` takes fewer seeds, not runs too short to get out: every network escapes at some gap, and the rates
    change with the gap (a quick look is not a flat picture of zeros)."""
    result, _ = run_study(load_study(_gap_py(tmp_path)), Settings(quick=True, out=tmp_path / "out"))
    rates = result.summary
    assert set(rates) == {"static", "plastic", "plastic, 3x the rates"}
    assert all(max(r) > 0 for r in rates.values()), rates
    assert all(min(r) < max(r) for r in rates.values()), rates
