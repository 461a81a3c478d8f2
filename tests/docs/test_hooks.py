"""The site's mkdocs hook: Sphinx roles in docstrings show as the names they cross-reference."""

from __future__ import annotations

import importlib.util
from pathlib import Path

_SPEC = importlib.util.spec_from_file_location("mkdocs_hooks", Path(__file__).resolve().parents[2] / "mkdocs_hooks.py")
hooks = importlib.util.module_from_spec(_SPEC)  # the hook lives beside mkdocs.yml, not in the package
_SPEC.loader.exec_module(hooks)
plain_roles = hooks.plain_roles


def test_roles_show_as_the_name_in_code():
    html = "see :class:<code>~neurowalk.sim.engine.Streaming</code> and :mod:<code>neurowalk.sim.batch</code>, ok"
    assert plain_roles(html) == "see <code>Streaming</code> and <code>neurowalk.sim.batch</code>, ok"
    assert plain_roles(":meth:<code>run</code>") == "<code>run</code>"
    assert plain_roles("<code>x</code> :note: plain") == "<code>x</code> :note: plain"
