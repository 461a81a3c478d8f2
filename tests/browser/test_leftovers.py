"""Chromium as the browser tests drive it leaves nothing behind: neither the page loads nor the DevTools-driven
browser leave their profile or their ``org.chromium.Chromium.*`` folders in the temporary folder (a stopped
Chromium leaves the latter where its TMPDIR points)."""

from __future__ import annotations

import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest
from cdp import Browser
from site_check import CHROMIUM, load

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no chromium (Debian's package; .ci/run installs it)")


@pytest.fixture
def temp() -> Iterator[Path]:
    """A short temporary folder (Chromium's socket paths inside it must fit 107 bytes: pytest's are too long)."""
    folder = Path(tempfile.mkdtemp(prefix="nwc", dir="/tmp"))
    yield folder
    shutil.rmtree(folder)


def test_chromium_leaves_nothing_in_the_temporary_folder(
    temp: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TMPDIR", str(temp))  # where Chromium puts its own temporary folders
    monkeypatch.setattr(tempfile, "tempdir", str(temp))  # where the tests' helpers make theirs
    page = tmp_path / "page.html"
    page.write_text("<html><body><p>here</p></body></html>")
    dom, _console = load(page.as_uri(), budget_ms=500)
    assert "<p>here</p>" in dom
    with Browser() as b:
        b.open(page.as_uri(), settle_s=0.5)
        assert b.evaluate("document.querySelector('p').textContent") == "here"
    assert sorted(p.name for p in temp.iterdir()) == []
