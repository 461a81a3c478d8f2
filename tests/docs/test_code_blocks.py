"""Every code block of the README and the site runs as written (tests/docs/doc_blocks.py says how each is tested).

A page is one test: its blocks run in order in a fresh empty folder, as a reader follows it, with this environment's
``neurowalk`` and ``python`` first on the PATH; its ``python`` blocks share one namespace.
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from doc_blocks import Block, blocks, commands, pages

BIN = str(Path(sys.executable).parent)
TIMEOUT_S = 300  # a block that takes longer belongs to `test: parse`


def _params() -> list:
    out = []
    for page in pages():
        found = blocks(page)
        if found:
            marks = [pytest.mark.slow] if any(b.kind == "slow" for b in found) else []
            out.append(pytest.param(page, id=page, marks=marks))
    return out


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = BIN + os.pathsep + env.get("PATH", "")
    env.setdefault("MUJOCO_GL", "egl")
    return env


def run_blocks(found: list[Block], folder: Path) -> list[str]:
    """Run ``found`` in order in ``folder``; the skipped ones' reasons."""
    namespace: dict = {"__name__": "__main__"}
    skipped = []
    old = Path.cwd()
    os.chdir(folder)
    try:
        for block in found:
            if block.kind == "skip":
                skipped.append(f"{block.id}: {block.why}")
            elif block.kind == "parse":
                _parse(block)
            elif block.lang == "python":
                exec(compile(block.code, block.id, "exec"), namespace)
            else:
                argv = ["bash", "-e", "-o", "pipefail", "-c", block.code]
                done = subprocess.run(argv, env=_env(), capture_output=True, text=True, timeout=TIMEOUT_S)
                assert done.returncode == 0, (
                    f"{block.id} failed ({done.returncode}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
                )
    finally:
        os.chdir(old)
    return skipped


@pytest.mark.parametrize("page", _params())
def test_code_blocks_of(page: str, tmp_path: Path) -> None:
    run_blocks(blocks(page), tmp_path)


def _parse(block: Block) -> None:
    """A block too long to run: every command in it is a ``neurowalk`` command its parser takes (or, in Python,
    code that compiles)."""
    from neurowalk.cli import parse

    if block.lang == "python":
        compile(block.code, block.id, "exec")
        return
    cmds = commands(block.code)
    assert cmds, block.id
    for cmd in cmds:
        argv = shlex.split(cmd)
        assert argv[0] in ("neurowalk", ".venv/bin/neurowalk"), f"{block.id}: only neurowalk commands parse: {cmd}"
        parse(argv[1:])  # raises UsageError naming what no longer parses


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
