"""mkdocs hooks of the documentation site (``hooks:`` in ``mkdocs.yml``).

The package's docstrings cross-reference in Sphinx's roles (``:class:`~neurowalk.sim.engine.Streaming```), which
the API pages' generator (mkdocstrings) leaves as text: ":class:" beside the name. :func:`plain_roles` shows such a
reference as the name in code, the way Sphinx shows it (``~`` keeps the last part only).
"""

from __future__ import annotations

import re
from typing import Any

_ROLE = re.compile(r":(?:class|func|meth|mod|data|attr|exc|obj|const):<code>(~?)([^<]+)</code>")


def plain_roles(html: str) -> str:
    """``html`` with every rendered Sphinx role (":class:<code>X</code>") shown as ``<code>X</code>``."""
    return _ROLE.sub(lambda m: f"<code>{m.group(2).rsplit('.', 1)[-1] if m.group(1) else m.group(2)}</code>", html)


def on_page_content(html: str, **kwargs: Any) -> str:
    """mkdocs' hook: each page's HTML, once its markdown (and the API's docstrings) is rendered."""
    return plain_roles(html)
