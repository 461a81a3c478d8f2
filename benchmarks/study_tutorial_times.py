"""How long the study tutorial's commands take (docs/tutorials/study.md states these times).

Writes the page's study file ``gap.py`` (its first Python block) into a temporary folder and runs there, each
``--repeats`` times into a fresh output folder (a study would otherwise go on from its finished runs): the quick
look (``--quick``), the whole study, and the longer study the page stops by hand (``--seeds 100 --workers 1``),
the numba cache warm (one run of each first, not counted). Each time is the median wall time of the command in a
child process, as a person typing it waits for it.

Run: ``python benchmarks/study_tutorial_times.py [--repeats 3] [--out docs/benchmarks/study_tutorial.json]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from neurowalk.fileio import write_json

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "tutorials" / "study.md"
#: name -> the arguments after ``neurowalk study gap.py`` (``--out`` is added).
COMMANDS = {
    "quick": ["--quick"],
    "study": [],
    "stop_by_hand": ["--seeds", "100", "--workers", "1"],
}


def study_file() -> str:
    """The page's study file: its first Python block."""
    return re.search(r"```python\n(.*?)```", PAGE.read_text(encoding="utf-8"), re.S).group(1)  # type: ignore[union-attr]


def timed(args: list[str], folder: Path, out: Path) -> float:
    """Wall time (s) of ``neurowalk study gap.py ARGS --out OUT`` in a child process run in ``folder``."""
    exe = Path(sys.executable).with_name("neurowalk")
    t = time.perf_counter()
    subprocess.run([str(exe), "study", "gap.py", *args, "--out", str(out)], cwd=folder, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "benchmarks" / "study_tutorial.json")
    args = ap.parse_args()
    out: dict = {"cores": os.cpu_count(), "machine": f"{platform.system()} {platform.machine()}", "commands": {}}
    with tempfile.TemporaryDirectory(prefix="study-tutorial-") as tmp:
        folder = Path(tmp)
        (folder / "gap.py").write_text(study_file(), encoding="utf-8")
        for name, extra in COMMANDS.items():
            timed(extra, folder, folder / f"warm-{name}")  # the numba cache warm, not counted
            times = [timed(extra, folder, folder / f"{name}-{k}") for k in range(args.repeats)]
            out["commands"][name] = {
                "command": " ".join(["neurowalk", "study", "gap.py", *extra]),
                "wall_s": round(statistics.median(times), 1),
                "runs_s": [round(t, 2) for t in times],
            }
            print(f"{name}: {out['commands'][name]['wall_s']} s", flush=True)
    write_json(args.out, out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
