"""Write docs/api.md, the Python API in brief: each documented name's signature and the first line of its docstring,
as plain Markdown that reads on GitHub too, grouped as docs/api-full.md groups them (that page, the whole docstrings,
is rendered by mkdocstrings on the site). ``tests/test_api_docs.py`` holds the committed page to what this makes.

Run: ``python tools/api_page.py`` (writes docs/api.md).
"""

from __future__ import annotations

import importlib
import inspect
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FULL = ROOT / "docs" / "api-full.md"
PAGE = ROOT / "docs" / "api.md"
HEAD = """# Python API

The names most scripts need are importable from the package itself (`from neurowalk import EpisodeConfig,
run_episode, ...`). Each is listed here with its signature and what it is, in a line; its whole documentation (every
argument, field and unit) is in [the full reference](api-full.md), on the documentation site. Units are SI (metres,
seconds, radians) unless a name says otherwise.

<!-- made by tools/api_page.py from the names of docs/api-full.md: edit those, then run it -->
"""


def documented() -> list[tuple[str, list[str]]]:
    """The full page's sections in order: (title, [dotted path of each ``:::`` entry])."""
    sections: list[tuple[str, list[str]]] = []
    for line in FULL.read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            sections.append((line[3:].strip(), []))
        elif line.startswith("::: ") and sections:
            sections[-1][1].append(line[4:].strip())
    return sections


def signature(name: str, obj: object) -> str:
    """``name(args) -> result`` of a function or class (a dataclass: its fields as its constructor takes them), the
    annotations as written in the source."""
    try:
        sig = inspect.signature(obj)  # type: ignore[arg-type]
    except (TypeError, ValueError):  # a constant, or a builtin without one
        return name
    parts, star = [], False
    for p in sig.parameters.values():
        if p.kind is p.KEYWORD_ONLY and not star:
            parts.append("*")
            star = True
        star = star or p.kind is p.VAR_POSITIONAL
        prefix = {p.VAR_POSITIONAL: "*", p.VAR_KEYWORD: "**"}.get(p.kind, "")
        text = prefix + p.name + (f": {_annotation(p.annotation)}" if p.annotation is not p.empty else "")
        if p.default is not p.empty:
            default = _default(p.default)
            text += f" = {default}" if p.annotation is not p.empty else f"={default}"
        parts.append(text)
    result = ""
    if sig.return_annotation is not sig.empty and not inspect.isclass(obj):
        result = f" -> {_annotation(sig.return_annotation)}"
    return f"{'class ' if inspect.isclass(obj) else ''}{name}({', '.join(parts)}){result}"


def _default(value: object) -> str:
    """A default as a reader would write it: its repr, a function or class by its name, ``...`` for an object whose
    repr names its memory address (it would change on every run)."""
    text = repr(value)
    if " at 0x" not in text:
        return text
    return getattr(value, "__name__", "...")


def _annotation(a: object) -> str:
    """An annotation as the source writes it (postponed: already its text)."""
    return a if isinstance(a, str) else inspect.formatannotation(a)


def first_line(obj: object) -> str:
    """The first sentence of its docstring, Sphinx's roles and double backquotes made plain Markdown."""
    doc = " ".join((inspect.getdoc(obj) or "").split("\n\n", 1)[0].split())
    doc = re.sub(r":\w+:`~?([\w.]+\.)?([\w]+)`", r"`\2`", doc)  # :class:`~a.b.Name` -> `Name`
    doc = doc.replace("``", "`")
    end = re.search(r"\.(\s|$)", doc)
    return doc[: end.start() + 1] if end else doc


def anchor(path: str) -> str:
    """The full page's anchor of an entry (mkdocstrings: its dotted path)."""
    return f"api-full.md#{path}"


def markdown() -> str:
    """docs/api.md as it should be."""
    out = [HEAD]
    for title, paths in documented():
        out.append(f"## {title}\n")
        for path in paths:
            module, _, name = path.rpartition(".")
            obj = getattr(importlib.import_module(module), name)
            out.append(f"[`{name}`]({anchor(path)}) (`{module}`): {first_line(obj)}\n")
            out.append(f"```python\n{signature(name, obj)}\n```\n")
    return "\n".join(out).rstrip() + "\n"


def main() -> int:
    PAGE.write_text(markdown(), encoding="utf-8")
    print(f"wrote {PAGE}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
