"""The site's gallery page (``docs/gallery.md``): every figure of ``neurowalk figure list``, as the committed full
reproduction drew it, with what it shows and its verdict.

``python -m neurowalk.experiments.reproduce.gallery docs/results docs/gallery.md`` writes it; a test holds the
committed page equal to :func:`gallery` of the committed results.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

from neurowalk.experiments import FIGURES
from neurowalk.experiments.reproduce.plan import PLAN
from neurowalk.experiments.reproduce.report import read_records

HEADER = """# The figures

Every figure neurowalk draws, as the committed full reproduction drew it (`neurowalk reproduce`; each figure's
numbers are in the json beside its picture, and `neurowalk figure NAME --replot --out DIR` redraws it from them).
Under each: what the paper shows, the verdict, and a link to the result's section of [the report](%s), where
every claim is set against the paper's value.
"""


def gallery(results: Path, page: Path) -> str:
    """The gallery's markdown for the full records in ``results``, with links relative to the page at ``page``."""
    records = read_records(results, quick=False)
    rel = Path(os.path.relpath(results, page.parent))
    lines = [HEADER % (rel / "report.md").as_posix()]
    order = list(dict.fromkeys(i.figure for i in PLAN if i.figure in FIGURES))  # the paper's order
    for name in order:
        exp = FIGURES[name]
        lines += [f"## {name}", "", f"{exp.title[:1].upper()}{exp.title[1:]}.", ""]
        items = [i for i in PLAN if i.figure == name and i.name in records]
        if not items:
            lines += ["Not in the committed reproduction yet: `neurowalk figure " + name + "` draws it.", ""]
        for item in items:
            rec = records[item.name]
            png = (rel / rec["files"]["png"]).as_posix()  # the record names it relative to the results
            report = (rel / "report.md").as_posix()
            lines += [
                f"![{item.name}]({png})",
                "",
                f"**{item.name}**: {item.paper}. Verdict: {rec['verdict']} "
                f"([report]({report}#{item.name})). `{rec['command']}`, {rec['wall_time_s']:.0f} s.",
                "",
            ]
    return "\n".join(lines).rstrip() + "\n"


def main(argv: list[str] | None = None) -> int:
    """``gallery.py RESULTS PAGE``: write the page."""
    results, page = (Path(a) for a in (sys.argv[1:] if argv is None else argv))
    page.write_text(gallery(results, page), encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
