"""The tutorial "Your own experiment": its study file, run again, gives the committed picture's numbers exactly."""

from __future__ import annotations

import json
from pathlib import Path

from doc_blocks import ROOT, blocks

from neurowalk import Settings, load_study, run_study

PAGE = "docs/tutorials/study.md"
COMMITTED = ROOT / "docs/studies/gap/gap.json"


def test_the_tutorial_study_gives_the_committed_numbers(tmp_path: Path) -> None:
    (block,) = [b for b in blocks(PAGE) if b.kind == "file"]
    assert block.why == "gap.py" and len(block.code.splitlines()) <= 30  # the "at most 30 lines"
    (tmp_path / "gap.py").write_text(block.code)
    result, files = run_study(load_study(tmp_path / "gap.py"), Settings(out=tmp_path / "out"))
    assert result.summary == json.loads(COMMITTED.read_text())
    assert {p.name for p in files.values()} == {"gap.png", "gap.json"}
