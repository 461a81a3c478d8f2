"""How long the README's test command takes: the whole suite on two processes, and the quick check without the
tests marked slow (the README states both).

Runs ``pytest -n 2`` and ``pytest -n 2 -m "not slow"`` in the repository (each once, in that order, the numba
cache as the first left it), and records each one's wall time and its count of tests by outcome (pytest's last
line). Run it on an otherwise idle machine: the suite uses both cores.

Run: ``python benchmarks/test_suite_times.py [--out docs/benchmarks/test_suite.json]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import subprocess
import sys
import time
from pathlib import Path

from neurowalk.fileio import write_json

ROOT = Path(__file__).resolve().parents[1]
RUNS = {"all": ["-n", "2"], "not_slow": ["-n", "2", "-m", "not slow"]}


def outcomes(last_line: str) -> dict[str, int]:
    """``{"passed": 1756, "skipped": 19, ...}`` from pytest's summary line."""
    return {word: int(n) for n, word in re.findall(r"(\d+) (passed|failed|skipped|xfailed|xpassed|errors?)", last_line)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "benchmarks" / "test_suite.json")
    args = ap.parse_args()
    out: dict = {"cores": os.cpu_count(), "machine": f"{platform.system()} {platform.machine()}", "runs": {}}
    for name, extra in RUNS.items():
        t = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *extra], cwd=ROOT,
                              capture_output=True, text=True)  # fmt: skip
        wall = time.perf_counter() - t
        last = done.stdout.strip().splitlines()[-1]
        out["runs"][name] = {
            "command": " ".join(["pytest", *extra]),
            "wall_s": round(wall),
            "minutes": round(wall / 60, 1),
            "exit_status": done.returncode,
            "tests": outcomes(last),
        }
        print(f"{name}: {wall:.0f} s, {last}", flush=True)
        for line in done.stdout.splitlines():  # what failed, by name (pytest's -ra summary)
            if line.startswith(("FAILED", "ERROR")):
                print(f"  {line}", flush=True)
    write_json(args.out, out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
