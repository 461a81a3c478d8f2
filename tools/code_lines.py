"""Count the lines of code of src/neurowalk at git revisions: Python lines that hold a token, docstrings, comments
and blank lines not counted (the measure of issue 60's "N lines of code shorter").

A line counts when a token other than a comment, a newline or an indent starts or continues on it, unless it lies in
a docstring (the first statement of a module, class or function, when it is a string). Each revision is read with
``git archive``, so the working tree is not touched.

Run: ``python tools/code_lines.py 8a0b7fd ebd0f10 HEAD`` (totals), ``--files`` for each file's count too.
"""

from __future__ import annotations

import argparse
import ast
import io
import subprocess
import tarfile
import tokenize

SKIP = {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT, tokenize.ENDMARKER}


def code_lines(source: str) -> int:
    """The lines of code of one Python source (see the module text)."""
    docs: set[int] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef) and node.body:
            first = node.body[0]
            value = first.value if isinstance(first, ast.Expr) else None
            if isinstance(value, ast.Constant) and isinstance(value.value, str):
                docs.update(range(first.lineno, (first.end_lineno or first.lineno) + 1))
    lines: set[int] = set()
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type not in SKIP:
            lines.update(n for n in range(tok.start[0], tok.end[0] + 1) if n not in docs)
    return len(lines)


def files_at(rev: str, folder: str = "src/neurowalk") -> dict[str, int]:
    """Path -> lines of code of every ``.py`` file under ``folder`` at git revision ``rev``."""
    tar = subprocess.run(["git", "archive", rev, folder], capture_output=True, check=True).stdout
    out = {}
    with tarfile.open(fileobj=io.BytesIO(tar)) as t:
        for member in t.getmembers():
            if member.isfile() and member.name.endswith(".py"):
                f = t.extractfile(member)
                assert f is not None
                out[member.name] = code_lines(f.read().decode())
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("revs", nargs="+", help="git revisions")
    ap.add_argument("--files", action="store_true", help="each file's count too")
    args = ap.parse_args()
    for rev in args.revs:
        counts = files_at(rev)
        if args.files:
            for path, n in sorted(counts.items(), key=lambda kv: -kv[1]):
                print(f"{n:6d} {path}")
        print(f"{rev}: {sum(counts.values())} lines of code in {len(counts)} files")


if __name__ == "__main__":
    main()
