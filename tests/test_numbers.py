"""Every number in the README and the docs comes from a committed result file (tests/numbers_checker.py), and every
relative link in them points to a file that is there."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from numbers_checker import LINK, problems, prose

ROOT = Path(__file__).resolve().parents[1]
#: The committed `neurowalk reproduce` run: generated, and the source of the numbers, not a page to check.
RESULTS = "docs/results/"
IMAGE = re.compile(r"!\[[^\]]*\]\(([^)\s]+)\)")


#: Pages made by code from a source the tests hold them equal to: the parser (tests/test_cli_reference.py) and the
#: committed reproduction's records (tests/experiments/reproduce/test_committed.py).
GENERATED = ("docs/cli.md", "docs/gallery.md", "docs/api.md")


def _pages() -> list[str]:
    docs = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md"))
    return ["README.md", *(p for p in docs if not p.startswith(RESULTS) and p not in GENERATED)]


def _slug(heading: str) -> str:
    """The anchor GitHub gives a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _anchors(page: Path) -> set[str]:
    return {_slug(m.group(1)) for m in re.finditer(r"^#+\s+(.*)$", prose(page.read_text(encoding="utf-8")), re.M)}


def test_the_pages_are_found():
    pages = _pages()
    for page in ("README.md", "docs/usage.md", "docs/experiments.md", "docs/paper-vs-code.md"):
        assert page in pages
    for page in ("docs/bodies.md", "docs/performance.md", "docs/baselines.md", "docs/optimize/README.md"):
        assert page in pages
    assert "docs/architecture.md" in pages


@pytest.mark.parametrize("page", _pages())
def test_every_number_has_a_source(page):
    assert problems(ROOT, ROOT / page) == []


@pytest.mark.parametrize("page", _pages())
def test_every_relative_link_points_to_a_file(page):
    doc = ROOT / page
    text = doc.read_text(encoding="utf-8")
    targets = [m.group(2) for m in LINK.finditer(prose(text))] + IMAGE.findall(text)
    missing = []
    for target in targets:
        if re.match(r"[a-z]+:", target):  # https:, mailto:
            continue
        file, _, anchor = target.partition("#")
        path = (doc.parent / file).resolve() if file else doc
        rel = path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else str(path)
        if not path.exists():
            missing.append(f"{target}: no such file")
        elif anchor and path.suffix == ".md" and anchor not in _anchors(path):
            missing.append(f"{target}: no heading #{anchor} in {rel}")
    assert missing == [], f"{page}: {missing}"
