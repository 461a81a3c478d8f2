"""The site's mkdocs hooks: Sphinx roles in docstrings show as links to what they name, and every link to a number
lands on its row of a numbers page. They need the `docs` extra (mkdocs), which .ci/run installs before it runs them
with the site's browser test."""

from __future__ import annotations

import importlib.util
import json
import re
from pathlib import Path
from urllib.parse import unquote

import pytest

pytest.importorskip("mkdocs", reason="the site's hooks need the docs extra (mkdocs)")

_SPEC = importlib.util.spec_from_file_location("mkdocs_hooks", Path(__file__).resolve().parents[2] / "mkdocs_hooks.py")
hooks = importlib.util.module_from_spec(_SPEC)  # the hook lives beside mkdocs.yml, not in the package
_SPEC.loader.exec_module(hooks)
plain_roles = hooks.plain_roles


def test_roles_show_as_the_name_in_code_linked_where_documented():
    html = (
        "see :class:<code>~neurowalk.sim.engine_interface.Streaming</code> and "
        ":mod:<code>neurowalk.sim.batch</code>, ok"
    )
    assert plain_roles(html) == (
        'see <autoref identifier="neurowalk.sim.engine_interface.Streaming" optional><code>Streaming</code></autoref>'
        " and "
        '<autoref identifier="neurowalk.sim.batch" optional><code>neurowalk.sim.batch</code></autoref>, ok'
    )
    assert plain_roles(":meth:<code>run</code>") == '<autoref identifier="run" optional><code>run</code></autoref>'
    assert plain_roles("<code>x</code> :note: plain") == "<code>x</code> :note: plain"
    # a short name is the entry of that name on the page, where there is one
    page = '<h2 id="neurowalk.sim.engine_interface.Streaming">Streaming</h2> see :class:<code>Streaming</code>'
    assert '<autoref identifier="neurowalk.sim.engine_interface.Streaming" optional>' in plain_roles(page)


def test_the_built_api_page_links_its_cross_references():
    """On the written site (where one was built), a role naming a documented class is a link to its entry."""
    api = Path(__file__).resolve().parents[2] / "site" / "api" / "index.html"
    if not api.is_file():
        pytest.skip("no built site (mkdocs build)")
    text = api.read_text(encoding="utf-8")
    assert ":class:" not in text and "<autoref" not in text
    assert re.search(r'<a class="autorefs autorefs-internal"[^>]*href="#neurowalk\.[\w.]+"', text)


def test_a_number_link_points_at_its_row_on_the_numbers_page():
    md = "ran [2](../benchmarks/bench.json#machine/cores) and [x](../benchmarks/bench.json) and [a](b.md#c)"
    out = hooks.to_numbers(md, "tutorials/run.md", {"benchmarks/bench.json"})
    assert out == (
        "ran [2](../numbers/benchmarks-bench.md#k.machine.cores) and [x](../benchmarks/bench.json) and [a](b.md#c)"
    )
    # a file without a numbers page keeps its link
    assert hooks.to_numbers(md, "tutorials/run.md", set()) == md
    assert hooks.anchor("rows/with%20space/0") == "k.rows.with_space.0"


def test_the_numbers_page_has_a_row_for_every_leaf_and_every_linked_key():
    data = {"a": {"b": [1, 2.5], "c": "text <b>"}, "d": None}
    page = hooks.numbers_page("results/x.json", data, {"a/b"})
    for key in ("a.b", "a.b.0", "a.b.1", "a.c", "d"):
        assert f'<tr id="k.{key}">' in page
    assert '<tr id="k.a">' not in page  # an inner key nobody links to has no row of its own
    assert "text &lt;b&gt;" in page and "<td>[1, 2.5]</td>" in page and "<td>null</td>" in page
    assert "[`results/x.json`](../results-x.json)" not in page and "(../results/x.json)" in page


def test_a_list_element_is_read_by_what_it_is():
    data = {"claims": [{"what": "escapes", "measured": "9/10"}], "rows": [{"layer": "omp", "hogs": 2, "rate": 1.5}]}
    page = hooks.numbers_page("results/x.json", data, set())
    assert '<tr id="k.claims.0.measured"><td><code>claims/[escapes]/measured</code></td><td>9/10</td></tr>' in page
    assert '<tr id="k.rows.0.rate"><td><code>rows/[layer omp, hogs 2]/rate</code></td><td>1.5</td></tr>' in page
    page = hooks.numbers_page("results/y.json", {"xs": [[0.5, 1.0]]}, set())  # a bare value: by its position
    assert '<tr id="k.xs.0.1"><td><code>xs/0/1</code></td><td>1.0</td></tr>' in page


def test_every_number_link_of_the_docs_lands_on_a_row():
    """Each ``file.json#key`` link of the docs: its numbers page (built from the committed file) has the key's row."""
    docs = Path(__file__).resolve().parents[2] / "docs"
    links = 0
    for page in docs.rglob("*.md"):
        for m in hooks._NUMBER_LINK.finditer(page.read_text(encoding="utf-8")):
            source = (page.parent / m.group(1)).resolve()
            if not source.is_relative_to(docs) or not source.is_file():
                continue
            uri = source.relative_to(docs).as_posix()
            data = json.loads(source.read_text(encoding="utf-8"))
            rendered = hooks.numbers_page(uri, data, {unquote(m.group(2))})
            assert f'<tr id="{hooks.anchor(m.group(2))}">' in rendered, (page.name, m.group(0))
            links += 1
    assert links > 200  # the docs' numbers do link here (the count was 268 when this test was written)
