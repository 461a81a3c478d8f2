"""The Python API page answers "what do I pass?": every field of every public dataclass it documents has an entry
in its docstring's Attributes (or Args) section, which the page's generator renders as a table."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import re
from pathlib import Path

PAGE = Path(__file__).parents[1] / "docs" / "api.md"
#: An entry of a Google-style section: "    name: text" or "    name (type): text".
ENTRY = re.compile(r"^ {4}(\w+)(?: \([^)]*\))?: ", re.M)


def _documented() -> dict[str, type]:
    """The dataclasses of the API page (``::: dotted.path`` lines), by their path."""
    out = {}
    for path in re.findall(r"^::: (\S+)", PAGE.read_text(encoding="utf-8"), re.M):
        module, _, name = path.rpartition(".")
        obj = getattr(importlib.import_module(module), name)
        if dataclasses.is_dataclass(obj):
            out[path] = obj
    return out


def test_every_field_of_a_documented_dataclass_has_an_entry():
    found = _documented()
    assert len(found) >= 8  # the page documents the config, the summary, the settings, ...
    for path, cls in found.items():
        entries = set(ENTRY.findall(inspect.getdoc(cls) or ""))
        missing = [f.name for f in dataclasses.fields(cls) if f.name not in entries]
        assert not missing, f"{path}: fields without documentation: {missing}"
