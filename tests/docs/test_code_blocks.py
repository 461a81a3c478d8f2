"""Every code block of the README and the site runs as written (tests/docs/doc_blocks.py says how each is tested).

A page is one test: its blocks run in order in a fresh empty folder, as a reader follows it, with this environment's
``neurowalk`` and ``python`` first on the PATH; its ``python`` blocks share one namespace.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from doc_blocks import TIMEOUT_S, Block, blocks, pages, run_blocks

HERE = Path(__file__).parent


def _params() -> list:
    out = []
    for page in pages():
        found = blocks(page)
        if found:
            marks = [pytest.mark.slow] if any(b.kind == "slow" for b in found) else []
            out.append(pytest.param(page, id=page, marks=marks))
    return out


@pytest.mark.parametrize("page", _params())
def test_code_blocks_of(page: str, tmp_path: Path) -> None:
    """The page runs in a process of its own: what its code registers or changes stays there."""
    done = subprocess.run(
        [sys.executable, str(HERE / "doc_blocks.py"), page, str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S * len(blocks(page)),
    )
    assert done.returncode == 0, f"{page}:\n{done.stdout[-4000:]}\n{done.stderr[-4000:]}"


def test_the_blocks_are_found_and_most_run() -> None:
    """The collection sees the pages' blocks, and skipping stays the exception."""
    found = [b for page in pages() for b in blocks(page)]
    assert len(found) >= 10
    assert sum(b.kind == "skip" for b in found) <= len(found) // 4


def test_a_failing_block_fails(tmp_path: Path) -> None:
    """The runner notices a command that fails, and a command that no longer parses (the check can fail)."""
    bad = Block("x.md", 1, "bash", "neurowalk run --arena no-such-arena --out out/x\n", "run", "")
    with pytest.raises(AssertionError, match="failed"):
        run_blocks([bad], tmp_path)
    worse = Block("x.md", 1, "bash", "neurowalk run --no-such-flag 3\n", "parse", "long")
    with pytest.raises(Exception, match="no-such-flag"):
        run_blocks([worse], tmp_path)
    broken = Block("x.md", 1, "python", "import neurowalk\nneurowalk.no_such_name\n", "run", "")
    with pytest.raises(AttributeError):
        run_blocks([broken], tmp_path)


def test_blocks_of_a_page_share_a_folder_and_a_namespace(tmp_path: Path) -> None:
    steps = [
        Block("x.md", 1, "python", "from pathlib import Path\nPath('made.txt').write_text('1')\nx = 41\n", "run", ""),
        Block("x.md", 5, "bash", "test -f made.txt\n", "run", ""),
        Block("x.md", 9, "python", "assert x + 1 == 42\n", "run", ""),
    ]
    assert run_blocks(steps, tmp_path) == []


def test_an_output_block_is_compared_with_what_the_block_before_printed(tmp_path: Path) -> None:
    """`test: output`: its lines must be printed, in order, `...` standing for what varies; a wrong line fails."""
    shell = Block("x.md", 1, "bash", "echo 'sweep: 24 runs: 16 already done, in 0.9 s'\necho done\n", "run", "")
    said = Block("x.md", 5, "text", "sweep: 24 runs: 16 already done, in ... s\ndone\n", "output", "")
    assert run_blocks([shell, said], tmp_path) == []
    wrong = Block("x.md", 5, "text", "sweep: 24 runs: 0 already done, in ... s\n", "output", "")
    with pytest.raises(AssertionError, match="printed"):
        run_blocks([shell, wrong], tmp_path)
    swapped = Block("x.md", 5, "text", "done\nsweep: ...\n", "output", "")
    with pytest.raises(AssertionError, match="printed"):
        run_blocks([shell, swapped], tmp_path)
    python = Block("x.md", 1, "python", "print('turned', 87, 'deg')\n", "run", "")
    assert run_blocks([python, Block("x.md", 3, "text", "turned ... deg\n", "output", "")], tmp_path) == []
    with pytest.raises(AssertionError, match="printed"):
        run_blocks([python, Block("x.md", 3, "text", "turned ... rad\n", "output", "")], tmp_path)


def test_an_output_block_needs_a_block_that_ran(tmp_path: Path) -> None:
    skipped = Block("x.md", 1, "bash", "neurowalk view\n", "skip", "a window")
    with pytest.raises(AssertionError, match="follows no block that runs"):
        run_blocks([skipped, Block("x.md", 3, "text", "anything\n", "output", "")], tmp_path)


def test_the_output_directive_marks_text_blocks_only(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    page.write_text("```bash\necho hi\n```\n\n<!-- test: output -->\n```text\nhi\n```\n\n```text\nnot compared\n```\n")
    found = blocks(str(page))
    assert [(b.lang, b.kind) for b in found] == [("bash", "run"), ("text", "output")]
    page.write_text("<!-- test: output -->\n```bash\necho hi\n```\n")
    with pytest.raises(ValueError, match="marks a text block"):
        blocks(str(page))
