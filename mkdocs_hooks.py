"""mkdocs hooks of the documentation site (``hooks:`` in ``mkdocs.yml``).

The package's docstrings cross-reference in Sphinx's roles (``:class:`~neurowalk.sim.engine_interface.Streaming```),
which the API pages' generator (mkdocstrings) leaves as text: ":class:" beside the name. :func:`plain_roles` shows such
a reference as the name in code, the way Sphinx shows it (``~`` keeps the last part only), linked to its entry.

A number in the pages links to the committed JSON file it comes from, with its key path after ``#``
(``benchmarks/bench.json#surrogate/steps_per_s``, see tests/numbers_checker.py). A browser shows such a link as
the top of the raw file and ignores the key. So the site gets one page per linked file, ``numbers/NAME.md``
(:func:`numbers_page`), a table of every value of the file with an anchor per key, and :func:`to_numbers` points
each link at its row, which the page highlights; the page links on to the raw file.

A notebook (``notebooks/NAME.ipynb``) is shown as the page ``notebooks/NAME.md`` (:func:`notebook_page`): its
text cells, its code cells as Python blocks, their stored outputs (printed lines, pictures) below them, and a link
to the notebook file to download.
"""

from __future__ import annotations

import html as _html
import json
import posixpath
import re
from collections.abc import Iterator
from typing import Any
from urllib.parse import unquote

from mkdocs.structure.files import File, Files

#: A link to a JSON file with a key path: ``](path/file.json#key/path)``.
_NUMBER_LINK = re.compile(r"\]\(([^)\s#]+\.json)#([^)\s]*)\)")
#: The JSON files (docs-relative) that have a numbers page in this build (set by :func:`on_files`).
_PAGES: set[str] = set()
_ROLE = re.compile(r":(?:class|func|meth|mod|data|attr|exc|obj|const):<code>(~?)([^<]+)</code>")


def plain_roles(html: str) -> str:
    """``html`` with every rendered Sphinx role (":class:<code>X</code>") shown as ``<code>X</code>``, linked to X's
    entry in the API reference where it has one (an autorefs cross-reference, resolved when the site is written)."""

    # a short name (":class:`Streaming`", ":meth:`Settings.apply`") stands for the entry whose full name ends so on
    # the same page, where only one does
    entries: dict[str, set[str]] = {}
    for full in re.findall(r'id="(neurowalk\.[\w.]+)"', html):
        parts = full.split(".")
        for i in range(1, len(parts)):
            entries.setdefault(".".join(parts[i:]), set()).add(full)

    def name(m: re.Match[str]) -> str:
        target = m.group(2)
        shown = target.rsplit(".", 1)[-1] if m.group(1) else target
        if not target.startswith("neurowalk.") and len(entries.get(target, ())) == 1:
            (target,) = entries[target]
        return f'<autoref identifier="{target}" optional><code>{shown}</code></autoref>'

    return _ROLE.sub(name, html)


def on_page_content(html: str, **kwargs: Any) -> str:
    """mkdocs' hook: each page's HTML, once its markdown (and the API's docstrings) is rendered."""
    return plain_roles(html)


def anchor(key: str) -> str:
    """The HTML id of key path ``key`` (URL-encoded, as in a link) on a numbers page: ``/`` as ``.``, space ``_``."""
    return "k." + re.sub(r"[^\w.~-]", "_", unquote(key).replace("/", "."))


def numbers_uri(json_uri: str) -> str:
    """The docs-relative path of the numbers page of docs-relative ``json_uri`` (``benchmarks/bench.json``)."""
    return "numbers/" + json_uri.removesuffix(".json").replace("/", "-") + ".md"


def identity(item: object) -> str | None:
    """What an element of a list is, for a reader: its ``what`` or ``name`` where it has one, else its leading
    fields up to the first measured (float) one, at most two (``layer omp, hogs 0``); None for a bare value."""
    if not isinstance(item, dict):
        return None
    for k in ("what", "name"):
        if isinstance(item.get(k), str):
            return item[k]
    lead = []
    for k, v in list(item.items())[:2]:
        if isinstance(v, float | dict | list) or v is None:
            break
        lead.append(f"{k} {v}")
    return ", ".join(lead) or None


def _rows(value: object, key: str, linked: set[str], shown: str = "") -> Iterator[tuple[str, str, object]]:
    """(key path, the path as a reader reads it, value) of every leaf of ``value`` and of every linked inner key, in
    the file's order; a list's element is read by its :func:`identity` (``claims/[the static network escapes the
    simple dead end]/measured``), its link keyed by position all the same."""
    inner = isinstance(value, dict | list)
    if key and (not inner or key in linked):
        yield key, shown, value
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _rows(v, f"{key}/{k}" if key else str(k), linked, f"{shown}/{k}" if shown else str(k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            name = identity(v)
            part = str(i) if name is None else f"[{name}]"
            yield from _rows(v, f"{key}/{i}" if key else str(i), linked, f"{shown}/{part}" if shown else part)


def numbers_page(json_uri: str, data: object, linked: set[str]) -> str:
    """The markdown of the numbers page of ``json_uri`` holding ``data``; ``linked``: the (decoded) keys linked."""
    raw = posixpath.relpath(json_uri, posixpath.dirname(numbers_uri(json_uri)))
    lines = [
        "---",
        "search:",
        "  exclude: true",
        "---",
        "",
        f"# {json_uri}",
        "",
        f"Every value of [`{json_uri}`]({raw}) (committed with the code), by its key path (an element of a list by "
        "what it is, in brackets); the row a link pointed at is highlighted.",
        "",
        '<table class="numbers"><thead><tr><th>key</th><th>value</th></tr></thead><tbody>',
    ]
    for key, read, value in _rows(data, "", linked):
        shown = value if isinstance(value, str) else json.dumps(value)
        lines.append(
            f'<tr id="{anchor(key)}"><td><code>{_html.escape(read)}</code></td><td>{_html.escape(str(shown))}</td></tr>'
        )
    lines.append("</tbody></table>")
    return "\n".join(lines) + "\n"


def _linked(files: Files) -> dict[str, set[str]]:
    """Docs-relative JSON path -> the decoded keys that the site's pages link to."""
    found: dict[str, set[str]] = {}
    for file in files.documentation_pages():
        text = file.content_string
        for m in _NUMBER_LINK.finditer(text):
            uri = posixpath.normpath(posixpath.join(posixpath.dirname(file.src_uri), m.group(1)))
            if not uri.startswith("..") and files.get_file_from_path(uri) is not None:
                found.setdefault(uri, set()).add(unquote(m.group(2)))
    return found


def to_numbers(markdown: str, page_uri: str, pages: set[str]) -> str:
    """``markdown`` of page ``page_uri`` with each link to a key of a JSON file in ``pages`` pointed at its row."""

    def point(m: re.Match[str]) -> str:
        uri = posixpath.normpath(posixpath.join(posixpath.dirname(page_uri), m.group(1)))
        if uri not in pages:
            return m.group(0)
        target = posixpath.relpath(numbers_uri(uri), posixpath.dirname(page_uri) or ".")
        return f"]({target}#{anchor(m.group(2))})"

    return _NUMBER_LINK.sub(point, markdown)


def notebook_page(name: str, nb: dict[str, Any]) -> str:
    """The Markdown page of notebook ``name`` (its file beside the page): its cells in order, each code cell with its
    stored outputs (text as a text block, a picture inline)."""
    out = []
    for cell in nb["cells"]:
        source = "".join(cell["source"])
        if cell["cell_type"] == "markdown":
            out.append(source + "\n")
            if len(out) == 1:  # after the title and its introduction
                out.append(f"[Download the notebook]({name}) and run it in Jupyter.\n")
            continue
        out.append(f"```python\n{source}\n```\n")
        for o in cell.get("outputs", []):
            if o["output_type"] == "stream":
                out.append(f"```text\n{''.join(o['text']).rstrip()}\n```\n")
            elif "image/png" in o.get("data", {}):
                out.append(f"![a picture the cell drew](data:image/png;base64,{o['data']['image/png']})\n")
            elif "text/plain" in o.get("data", {}):
                out.append(f"```text\n{''.join(o['data']['text/plain']).rstrip()}\n```\n")
    return "\n".join(out)


def on_files(files: Files, config: Any, **kwargs: Any) -> Files:
    """mkdocs' hook: add a numbers page for each JSON file that a page links into, and a page for each notebook."""
    for f in list(files):
        if f.src_uri.startswith("notebooks/") and f.src_uri.endswith(".ipynb"):
            page = notebook_page(posixpath.basename(f.src_uri), json.loads(f.content_string))
            files.append(File.generated(config, f.src_uri.removesuffix(".ipynb") + ".md", content=page))
    linked = _linked(files)
    for uri, keys in sorted(linked.items()):
        data = json.loads(files.get_file_from_path(uri).content_string)
        files.append(File.generated(config, numbers_uri(uri), content=numbers_page(uri, data, keys)))
    _PAGES.clear()
    _PAGES.update(linked)
    return files


def on_page_markdown(markdown: str, page: Any, config: Any, **kwargs: Any) -> str:
    """mkdocs' hook: each page's markdown, before it is rendered: number links point at the numbers pages."""
    return to_numbers(markdown, page.file.src_uri, _PAGES)
