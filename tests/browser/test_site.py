"""The documentation site in a real browser (headless Chromium): every page loads whole, with its pictures and its
diagrams drawn, and nothing in the console. Needs the docs extra (mkdocs) and Debian's ``chromium`` (``.ci/run``
installs both, then runs these tests); Mermaid's script, which draws the diagrams offline, is committed in
``docs/javascripts/``."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from site_check import CHROMIUM, MERMAID_SOURCE, pages, problems, screenshots, serve

ROOT = Path(__file__).resolve().parents[2]

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="no chromium (Debian's package; .ci/run installs it)"),
    pytest.mark.skipif(
        subprocess.run([sys.executable, "-c", "import mkdocs"], capture_output=True).returncode != 0,
        reason="no mkdocs (pip install -e '.[docs]')",
    ),
]


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    build = [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)]
    subprocess.run(build, cwd=ROOT, check=True, capture_output=True, env=env)
    return out


def test_every_page_loads_whole_in_a_browser(site: Path, tmp_path: Path) -> None:
    found = pages(site)
    assert len(found) >= 20 and "" in found and "architecture/" in found
    with serve(site) as (base, missing):
        wrong = [p for page in found for p in problems(site, base, page, missing)]
        shots = screenshots(base, Path(os.environ.get("NEUROWALK_SCREENSHOTS") or tmp_path))
    assert not wrong, "\n".join(wrong)
    assert all(p.is_file() and p.stat().st_size > 10_000 for p in shots)  # a drawn page, not a blank one
    print("screenshots:", *shots)


def test_the_check_sees_what_a_reader_would(tmp_path: Path) -> None:
    """A page with a missing picture, a console error, a raw diagram, a dead link and a link to a place that its page
    does not have: each is reported."""
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "index.html").write_text('<html><body><p id="here">x</p></body></html>')
    (tmp_path / "index.html").write_text(
        '<html><body><img src="gone.png"><script>console.error("boom")</script>'
        '<pre class="mermaid"><code>flowchart LR\n a --> b</code></pre><a href="nowhere/">x</a>'
        '<a href="other/#here">fine</a><a href="other/#gone">y</a></body></html>'
    )
    with serve(tmp_path) as (base, missing):
        wrong = problems(tmp_path, base, "", missing)
    text = "\n".join(wrong)
    assert "gone.png" in text and "boom" in text and "Mermaid" in text and "nowhere/" in text, text
    assert "other/#gone" in text and "#here" not in text, text
    assert MERMAID_SOURCE.search('<pre class="mermaid"><code>flowchart LR')
