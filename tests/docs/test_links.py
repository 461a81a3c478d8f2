"""The README and the site point only at what is there, and speak to a reader, not of how the project is run.

Links (and images) are checked in tests/test_numbers.py; this checks the files a page names in inline code, the
pages the site's navigation lists, and the words of the pages.
"""

from __future__ import annotations

import re

import pytest
from doc_blocks import ROOT, pages

#: Where a path named in a page may be: the repository, the package, the docs, or the page's own folder.
BASES = ("", "src/", "src/neurowalk/", "docs/")
CODE = re.compile(r"`([^`\n]+)`")
#: A path named in inline code: a folder and a file with a known suffix, no placeholders.
PATH = re.compile(r"^[\w.\-/]+/[\w.\-]+\.(?:py|json|md|png|toml|yml|txt|npz|jsonl)$")
#: Paths that name what a command writes (outputs), not files of the repository.
WRITTEN = re.compile(r"^(?:out|DIR|site)/|/(?:summary|best|heldout|bench|cmaes|history|results)\.json$|trajectory")
#: Words of the project's own process, which mean nothing to a reader of the documentation.
PROCESS = re.compile(
    r"\bissues?\s+\d+|\bissue's\b|\bsessions?\b|\bacceptance\b|DESIGN\.md|original_code_facts|\.\./shared"
    r"|\b(?:this|last|next|earlier) round\b|\bTODO\b|\bFIXME\b|an earlier version of this page",
    re.I,
)


def _site_pages() -> list[str]:
    """The pages of the site's navigation (mkdocs.yml), relative to docs/."""
    text = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    nav = text[text.index("\nnav:") :]
    return re.findall(r":\s*([\w/\-.]+\.md)\s*$", nav, re.M)


def test_every_page_of_the_navigation_is_there_and_every_page_is_in_it():
    nav = _site_pages()
    assert "index.md" in nav and "cli.md" in nav and "api.md" in nav and "gallery.md" in nav
    made = {p for p in nav if (ROOT / "docs" / p).with_suffix(".ipynb").is_file()}  # a notebook's page (the hooks)
    missing = [p for p in nav if not (ROOT / "docs" / p).is_file() and p not in made]
    assert missing == []
    written = {p.removeprefix("docs/") for p in pages() if p.startswith("docs/")} | {"cli.md", "gallery.md"}
    assert sorted(written - set(nav)) == []  # a page outside the navigation is a page nobody finds


@pytest.mark.parametrize("page", pages())
def test_every_file_a_page_names_is_there(page):
    doc = ROOT / page
    missing = []
    for name in CODE.findall(doc.read_text(encoding="utf-8")):
        name = name.strip()
        if not PATH.match(name) or WRITTEN.search(name):
            continue
        places = [ROOT / base / name for base in BASES] + [doc.parent / name]
        if not any(p.exists() for p in places):
            missing.append(name)
    assert missing == [], f"{page} names files that are not in the repository: {missing}"


@pytest.mark.parametrize("page", pages())
def test_no_page_speaks_of_the_project_s_process(page):
    text = (ROOT / page).read_text(encoding="utf-8")
    found = [m.group(0) for m in PROCESS.finditer(text)]
    assert found == [], f"{page}: {found}"


def test_the_checks_catch_what_they_look_for(tmp_path):
    assert PROCESS.search("fixed in issue 26") and PROCESS.search("as DESIGN.md §3 says")
    assert not PROCESS.search("the robot walks round the box")
    assert PATH.match("body/amosii_mjcf.py") and not PATH.match("neurowalk run") and WRITTEN.search("out/run/run.png")
