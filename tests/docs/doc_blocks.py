"""The code blocks of the README and the documentation site, and how each one is tested.

A fenced block in ``bash`` or ``python`` is code a reader copies, so it is run, as a reader follows a page: the
page's blocks in order, in one empty folder, the ``python`` blocks in one namespace. The line before a fence may say
otherwise, in an HTML comment (invisible on the site and on GitHub):

- ``<!-- test: slow -->``: run, and the page's test is marked slow (it takes more than a few seconds);
- ``<!-- test: parse: WHY -->``: a block of commands too long for a test run (minutes to hours: the committed
  reproduction ran them); each ``neurowalk`` command in it is parsed by the command's own parser, so an option or
  a value that no longer exists fails;
- ``<!-- test: skip: WHY -->``: not run, for the reason given (it installs from the network, it opens a window);
- ``<!-- test: file: NAME -->``: a file the reader saves as NAME (e.g. a study): written to the folder, not run;
- ``<!-- test: output -->`` before a ``text`` block: the output the block before it prints (a ``bash`` block's
  stdout, a ``python`` block's ``print``). Each of its non-blank lines must match a line of that output, in the
  same order (other lines may come between); ``...`` in a line stands for any text (a time, a number that varies),
  the rest must be there as written.

Blocks in other languages (``text``, ``mermaid``, ``bibtex``, ``json``) are output or pictures, not code; a ``text``
block is compared with what the code printed only where ``test: output`` says so.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BIN = str(Path(sys.executable).parent)
TIMEOUT_S = 300  # a block that takes longer belongs to `test: parse`
#: Fences that hold code to run.
RUN = ("bash", "python")
KINDS = ("run", "slow", "parse", "skip", "file", "output")
#: Pages made by code (the CLI reference, the gallery): their blocks are output, not code to copy.
GENERATED = ("docs/cli.md", "docs/gallery.md", "docs/api.md")
_FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```\s*$", re.S | re.M)
_DIRECTIVE = re.compile(r"<!--\s*test:\s*(\w+)(?::\s*(.*?))?\s*-->\s*$")


@dataclass(frozen=True)
class Block:
    """One fenced block: its page (relative to the root), first line (1-based), language, code and test kind."""

    page: str
    line: int
    lang: str
    code: str
    kind: str
    why: str

    @property
    def id(self) -> str:
        return f"{self.page}:{self.line}"


def pages() -> list[str]:
    """The README and every page of the site but the generated ones (the report and the CLI reference)."""
    docs = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md"))
    return ["README.md", *(p for p in docs if not p.startswith("docs/results/") and p not in GENERATED)]


def blocks(page: str) -> list[Block]:
    """The runnable blocks of ``page`` with their test kind (see the module's text)."""
    text = (ROOT / page).read_text(encoding="utf-8")
    found = []
    for m in _FENCE.finditer(text):
        lang = m.group(1)
        before = text[: m.start()].rstrip("\n").rsplit("\n", 1)[-1]
        d = _DIRECTIVE.search(before)
        kind, why = (d.group(1), d.group(2) or "") if d else ("run", "")
        if lang not in RUN and not (lang == "text" and kind == "output"):
            continue
        if kind not in KINDS:
            raise ValueError(f"{page}: unknown test kind {kind!r} (one of {', '.join(KINDS)})")
        if (kind == "output") != (lang == "text"):
            raise ValueError(f"{page}: `test: output` marks a text block, the output of the block before it")
        if kind in ("parse", "skip", "file") and not why:
            raise ValueError(f"{page}: `test: {kind}` needs a reason")
        line = text.count("\n", 0, m.start()) + 1
        found.append(Block(page, line, lang, m.group(2), kind, why))
    return found


def commands(code: str) -> list[str]:
    """The shell commands of a bash block: continuation lines joined, comments and blank lines dropped, ``&&``
    chains split."""
    joined = re.sub(r"\\\n\s*", " ", code)
    out = []
    for line in joined.splitlines():
        line = re.split(r"(?:^|\s)#", line, maxsplit=1)[0].strip()
        out += [part.strip() for part in line.split("&&") if part.strip()]
    return out


def output_matches(expected: str, printed: str) -> bool:
    """Whether every non-blank line of ``expected`` matches a line of ``printed``, in order (``...``: any text)."""
    lines = iter(printed.splitlines())
    for want in filter(str.strip, expected.splitlines()):
        pattern = re.compile(".*?".join(re.escape(part) for part in want.strip().split("...")))
        if not any(pattern.fullmatch(line.strip()) for line in lines):
            return False
    return True


class _Tee(io.StringIO):
    """What a python block prints: kept, and shown as well."""

    def __init__(self, shown) -> None:
        super().__init__()
        self.shown = shown

    def write(self, text: str) -> int:
        self.shown.write(text)
        return super().write(text)


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = BIN + os.pathsep + env.get("PATH", "")
    env.setdefault("MUJOCO_GL", "egl")
    return env


def run_blocks(found: list[Block], folder: Path) -> list[str]:
    """Run ``found`` in order in ``folder``; the skipped ones' reasons."""
    namespace: dict = {"__name__": "__main__"}
    skipped = []
    printed: str | None = None  # what the last block run printed (None: the last block was not run)
    old = Path.cwd()
    os.environ.update(_env())  # python blocks that start a command find this environment's `neurowalk`, as bash's do
    os.chdir(folder)
    try:
        for block in found:
            if block.kind == "output":
                assert printed is not None, f"{block.id}: `test: output` follows no block that runs"
                assert output_matches(block.code, printed), (
                    f"{block.id}: the block before it printed\n{printed[-3000:]}\nnot\n{block.code}"
                )
                continue
            printed = None
            if block.kind == "skip":
                skipped.append(f"{block.id}: {block.why}")
            elif block.kind == "parse":
                _parse(block)
            elif block.kind == "file":
                if block.lang == "python":
                    compile(block.code, block.id, "exec")  # a file that no longer parses fails here
                Path(block.why).write_text(block.code, encoding="utf-8")
            elif block.lang == "python":
                with contextlib.redirect_stdout(_Tee(sys.stdout)) as out:
                    exec(compile(block.code, block.id, "exec"), namespace)
                printed = out.getvalue()
            else:
                argv = ["bash", "-e", "-o", "pipefail", "-c", block.code]
                done = subprocess.run(argv, env=_env(), capture_output=True, text=True, timeout=TIMEOUT_S)
                assert done.returncode == 0, (
                    f"{block.id} failed ({done.returncode}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
                )
                printed = done.stdout
    finally:
        os.chdir(old)
    return skipped


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


def main(argv: list[str]) -> int:
    """``doc_blocks.py PAGE FOLDER``: run the page's blocks in ``FOLDER`` (a test runs each page so, in a process
    of its own)."""
    page, folder = argv
    skipped = run_blocks(blocks(page), Path(folder))
    for line in skipped:
        print(f"skipped {line}")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT / "src"))
    raise SystemExit(main(sys.argv[1:]))
