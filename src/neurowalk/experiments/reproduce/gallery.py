"""The site's gallery page (``docs/gallery.md``): every figure of ``neurowalk figure list``, as the committed full
reproduction drew it, with what it shows and its verdict.

``python -m neurowalk.experiments.reproduce.gallery docs/results docs/gallery.md`` writes it; a test holds the
committed page equal to :func:`gallery` of the committed results. The page opens with two runs as 3-D replays side by
side (:data:`REPLAYS`, one self-contained HTML file each, in ``docs/replays/``): ``... gallery --replays docs/replays``
runs them and writes the files (``neurowalk run`` and ``neurowalk view --export``).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

from neurowalk.experiments import FIGURES
from neurowalk.experiments.reproduce.plan import PLAN, settings_words
from neurowalk.experiments.reproduce.report import read_records

HEADER = """# The figures

Every figure neurowalk draws, as the committed full reproduction drew it (`neurowalk reproduce`; each figure's
numbers are in the json beside its picture, and `neurowalk figure NAME --replot --out DIR` redraws it from them).
Under each: what the paper shows, the verdict, and a link to the result's section of [the report](%s), where
every claim is set against the paper's value.
"""


#: The replays the gallery embeds: file name -> (the `neurowalk run` arguments, the caption).
REPLAYS: dict[str, tuple[tuple[str, ...], str]] = {
    "fig5b-plastic": (
        ("--arena", "narrow-passage", "--controller", "plastic", "--steps", "5000"),
        "Fig. 5B's run: the plastic network escapes the narrow passage",
    ),
    "fig3b-static": (
        ("--arena", "narrow-passage", "--controller", "static", "--steps", "5000"),
        "Fig. 3B's run: the static network stays trapped in it",
    ),
}


#: From the gallery's page on the site (``gallery/``: mkdocs gives each page a folder) up to the site's root: raw
#: HTML's links are not rewritten by mkdocs as a markdown link is.
SITE_UP = "../"


def make_replays(folder: Path) -> list[Path]:
    """Run each of :data:`REPLAYS` and write its replay, ``folder/NAME.html``; the files written."""
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, (args, _) in REPLAYS.items():
            run = Path(tmp) / name
            neurowalk = [sys.executable, "-m", "neurowalk"]
            subprocess.run([*neurowalk, "run", *args, "--out", str(run)], check=True)
            subprocess.run([*neurowalk, "view", str(run), "--export", str(folder / f"{name}.html")], check=True)
            written.append(folder / f"{name}.html")
    return written


def _replays(page: Path) -> list[str]:
    """The page's replays, side by side (where their files are there)."""
    folder = page.parent / "replays"
    shown = [(name, caption) for name, (_, caption) in REPLAYS.items() if (folder / f"{name}.html").is_file()]
    if not shown:
        return []
    lines = [
        "## Two runs in 3-D",
        "",
        "Press play (bottom left), drag the time line, turn the view with the mouse. Each is one HTML file that "
        "plays with no server (`neurowalk view RUN_DIR --export FILE.html`; the page on serving a run, with its "
        "traces: [Look at a run](tutorials/view.md)).",
        "",
        '<div class="replays">',
    ]
    for name, caption in shown:
        lines += [
            f'<figure><iframe src="{SITE_UP}replays/{name}.html" title="{caption}" loading="lazy"></iframe>',
            f'<figcaption>{caption} (<a href="{SITE_UP}replays/{name}.html">open alone</a>)</figcaption></figure>',
        ]
    return [*lines, "</div>", ""]


def gallery(results: Path, page: Path) -> str:
    """The gallery's markdown for the full records in ``results``, with links relative to the page at ``page``."""
    records = read_records(results, quick=False)
    rel = Path(os.path.relpath(results, page.parent))
    lines = [HEADER % (rel / "report.md").as_posix(), *_replays(page)]
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
                f"([report]({report}#{item.name})). `neurowalk figure {rec['figure']}`, "
                f"{settings_words(rec['settings'])}: {rec['wall_time_s']:.0f} s.",
                "",
            ]
    return "\n".join(lines).rstrip() + "\n"


def main(argv: list[str] | None = None) -> int:
    """``gallery.py RESULTS PAGE``: write the page; ``gallery.py --replays FOLDER``: run and write the replays."""
    args = sys.argv[1:] if argv is None else argv
    if args[:1] == ["--replays"]:
        for path in make_replays(Path(args[1])):
            print(f"wrote {path}")
        return 0
    results, page = (Path(a) for a in args)
    page.write_text(gallery(results, page), encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
