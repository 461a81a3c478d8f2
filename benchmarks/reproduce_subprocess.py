"""What `neurowalk reproduce` pays for running each figure in a process of its own: a figure's command started as
a subprocess (``python -m neurowalk figure fig2 --quick``, the interpreter, neurowalk's imports and its kernels
loaded from numba's cache) against the same figure run again inside a process that has run it once (the price
of a subprocess, per figure), and how many figure runs a full reproduction makes.

    python benchmarks/reproduce_subprocess.py [--repeats 5] [--out docs/benchmarks/reproduce_subprocess.json]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

from neurowalk.cli import main
from neurowalk.experiments.reproduce.plan import PLAN
from neurowalk.experiments.reproduce.runner import runs_of
from neurowalk.fileio import write_json

COMMAND = ["figure", "fig2", "--quick"]


def measure(repeats: int) -> dict[str, object]:
    """Seconds of the figure as a subprocess and in this process (after a first, untimed run here), alternating."""
    sub, here = [], []
    with tempfile.TemporaryDirectory() as tmp:
        main([*COMMAND, "--out", f"{tmp}/warm"])  # this process: imports made, kernels loaded
        for i in range(repeats):
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "neurowalk", *COMMAND, "--out", f"{tmp}/s{i}"], check=True,
                           capture_output=True)  # fmt: skip
            sub.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            main([*COMMAND, "--out", f"{tmp}/h{i}"])
            here.append(time.perf_counter() - t0)
    runs, _ = runs_of(list(PLAN), quick=False, workers=None)
    cost = statistics.median(sub) - statistics.median(here)
    return {
        "command": "neurowalk " + " ".join(COMMAND),
        "subprocess_s": statistics.median(sub),
        "in_process_s": statistics.median(here),
        "cost_per_figure_s": cost,
        "figure_runs_in_reproduce": len(runs),
        "cost_in_reproduce_s": cost * len(runs),
        "repeats": {"subprocess": sub, "in_process": here},
    }


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--out", type=Path, default=Path("docs/benchmarks/reproduce_subprocess.json"))
    a = p.parse_args()
    result = measure(a.repeats)
    write_json(a.out, result)
    n, total = result["figure_runs_in_reproduce"], result["cost_in_reproduce_s"]
    print(f"a figure as a subprocess costs {result['cost_per_figure_s']:.2f} s more; {n} figure runs: {total:.0f} s")
