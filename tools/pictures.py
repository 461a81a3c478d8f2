"""Make again every picture in the README and docs/ that a documented command draws, where the page shows it.

Each picture is made by the command its page gives, in a temporary folder, and copied (with the numbers it is drawn
from) to where the page shows it. ``tests/docs/test_pictures.py`` holds the committed files to what the commands
make today. The figures of ``neurowalk reproduce`` (docs/results/), the baselines (docs/baselines/) and the
parameter search (docs/optimize/) are made by their own long commands and held by their own tests. The viewer's
picture (docs/tutorials/view.png) is headless Chromium's screenshot of the served replay at the step the page shows
(Debian's ``chromium``, the ``web`` extra, and tests/browser/cdp.py to drive it).

Run: ``python tools/pictures.py [NAME ...]`` (default: all of :data:`PICTURES`; ``--list`` names them).
"""

from __future__ import annotations

import argparse
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Picture:
    """A committed picture and the command that draws it.

    Attributes:
        command: the page's command, ``OUT`` standing for its output folder.
        files: ``{file the command writes: where it is committed}`` (relative to OUT and to the repository).
        page: the page that shows it (and gives the command).
    """

    command: str
    files: dict[str, str]
    page: str
    screenshot_step: int | None = None  # the served replay's step to take a screenshot of (``OUT/view.png``)
    study_file: str | None = None  # a page whose first Python block is the command's study file (``DIR/gap.py``)


def readme_command() -> str:
    """The README's first command's run (``neurowalk run ...``), its output folder written ``OUT``."""
    first = next(line for line in (ROOT / "README.md").read_text().splitlines() if "neurowalk run" in line)
    run = first[first.index("neurowalk run") :]
    args = shlex.split(run)
    args[args.index("--out") + 1] = "OUT"
    return shlex.join(args)


PICTURES: dict[str, Picture] = {
    "run": Picture(readme_command(), {"run.png": "docs/run.png", "summary.json": "docs/run.json"}, "README.md"),
    "view": Picture(
        "neurowalk run --arena narrow-passage --controller plastic --steps 5000 --out OUT --overwrite",
        {"view.png": "docs/tutorials/view.png", "summary.json": "docs/tutorials/view.json"},
        "docs/tutorials/view.md",
        screenshot_step=2600,
    ),
    "gap": Picture(
        "neurowalk study DIR/gap.py --out OUT",
        {"gap.png": "docs/studies/gap/gap.png", "gap.json": "docs/studies/gap/gap.json"},
        "docs/tutorials/study.md",
        study_file="docs/tutorials/study.md",
    ),
    "climb-height": Picture(
        "neurowalk study docs/studies/climb_height.py --out OUT",
        {
            "climb-height.png": "docs/studies/climb-height/climb-height.png",
            "climb-height.json": "docs/studies/climb-height/climb-height.json",
        },
        "docs/experiments.md",
    ),
}


def make(name: str, out: Path) -> dict[str, Path]:
    """Run picture ``name``'s command with its output in ``out``; the files it wrote, by their committed path."""
    pic = PICTURES[name]
    if pic.study_file is not None:  # the reader saves the page's study file and runs it
        page = (ROOT / pic.study_file).read_text(encoding="utf-8")
        (out.parent / "gap.py").write_text(re.search(r"```python\n(.*?)```", page, re.S).group(1), encoding="utf-8")  # type: ignore[union-attr]
    args = [a.replace("OUT", str(out)).replace("DIR", str(out.parent)) for a in shlex.split(pic.command)]
    exe = Path(sys.executable).with_name("neurowalk")
    subprocess.run([str(exe) if exe.exists() else "neurowalk", *args[1:]], cwd=ROOT, check=True)
    if pic.screenshot_step is not None:
        screenshot(out, pic.screenshot_step, out / "view.png")
    return {to: out / made for made, to in pic.files.items()}


def screenshot(run: Path, step: int, path: Path) -> None:
    """Write ``path``: Chromium's picture (1400 x 860) of run ``run``'s replay as ``neurowalk view`` serves it,
    moved to ``step``, once it has stopped changing (the notice of software WebGL closed)."""
    sys.path.insert(0, str(ROOT / "tests" / "browser"))
    from cdp import Browser

    from neurowalk.plotting.replay import load_replay
    from neurowalk.plotting.web import ReplayPage, free_port

    page = ReplayPage(load_replay(run), port=free_port())
    try:
        page.go(step)
        with Browser(1400, 860) as b:
            b.open(f"http://127.0.0.1:{page.server.get_port()}/")
            b.wait_for("document.querySelectorAll('canvas').length > 1")
            b.evaluate("document.querySelectorAll('.mantine-Notification-closeButton').forEach(x => x.click())")
            b.save(b.settled(), path)
    finally:
        page.close()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("names", nargs="*", help=f"pictures to make (default all: {', '.join(PICTURES)})")
    ap.add_argument("--list", action="store_true", help="print each picture's command and files, make none")
    args = ap.parse_args()
    unknown = [n for n in args.names if n not in PICTURES]
    if unknown:
        print(f"pictures.py: no picture {unknown[0]!r}; pictures: {', '.join(PICTURES)}", file=sys.stderr)
        return 2
    for name in args.names or list(PICTURES):
        pic = PICTURES[name]
        if args.list:
            print(f"{name}: {pic.command} ({pic.page}) -> {', '.join(pic.files.values())}")
            continue
        with tempfile.TemporaryDirectory(prefix=f"pictures-{name}-") as tmp:
            for to, made in make(name, Path(tmp) / name).items():
                shutil.copyfile(made, ROOT / to)
                print(f"{name}: wrote {to}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
