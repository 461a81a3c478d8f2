"""The Python API page answers "what do I pass?": every field of every public dataclass it documents has an entry
in its docstring's Attributes (or Args) section, which the page's generator renders as a table."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import re
from pathlib import Path

ROOT = Path(__file__).parents[1]
PAGE = ROOT / "docs" / "api-full.md"  # the whole docstrings, by mkdocstrings on the site
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


def test_the_api_page_in_brief_is_what_its_generator_makes_and_reads_without_the_site():
    import sys

    sys.path.insert(0, str(ROOT / "tools"))
    from api_page import markdown

    brief = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    assert brief == markdown(), "run: python tools/api_page.py"
    assert ":::" not in brief and ":class:" not in brief and ":func:" not in brief  # plain Markdown, on GitHub too
    full = re.findall(r"^::: (\S+)", PAGE.read_text(encoding="utf-8"), re.M)
    listed = re.findall(r"^\[`(\w+)`\]\(api-full\.md#([\w.]+)\)", brief, re.M)
    assert [path for _, path in listed] == full and all(path.endswith("." + name) for name, path in listed)
    assert "run_episode(cfg: EpisodeConfig, *, progress: bool = False" in brief  # a signature, as the source writes it


def test_every_public_name_is_on_the_api_pages():
    import neurowalk

    full = PAGE.read_text(encoding="utf-8")
    documented = {path.rpartition(".")[2] for path in re.findall(r"^::: (\S+)", full, re.M)}
    skip = {"__version__", "ACTUATORS", "LEGS", "ARENAS", "BODIES", "ENGINES"}  # constants: named on the pages' text
    missing = [n for n in neurowalk.__all__ if n not in documented and n not in skip]
    assert not missing, f"public names without an entry on docs/api-full.md: {missing}"
