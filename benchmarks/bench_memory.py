"""Peak memory of ``neurowalk run`` against its length: bounded by the part size, not by the step count.

For each body of ``--bodies`` (AMOSII in MuJoCo, and the planar surrogate, whose compiled loop streams its rows
the same way), runs ``neurowalk run --body BODY --arena difficult --controller plastic --steps N`` in a child
process for each ``N`` of ``--steps`` and reads the child's peak resident set size (``wait4``'s ``ru_maxrss``),
with the short run as the baseline measured in the same invocation (after a 5-step warm-up run that fills
numba's cache, so that compilation, which happens once, is not counted). The rows stream to
``trajectory.parts`` on disk; what the run keeps in memory is one part (10,000 rows), the summary's columns
(41 bytes a step) and a picture of at most 10,000 rows. A physics run keeping every row would need about 680
bytes a step more (842 MB at 1,000,000 steps).

Run: ``python benchmarks/bench_memory.py [--bodies amosii,surrogate] [--steps 2000,100000,1000000]
[--out out/bench]``; writes ``memory.json``. The 1,000,000-step physics run takes about 11 min on one core, the
surrogate's about 10 s.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def peak_mb(body: str, steps: int, folder: Path) -> tuple[float, float]:
    """(peak RSS in MB, wall time in s) of one ``neurowalk run`` of ``steps`` control steps."""
    cmd = [sys.executable, "-m", "neurowalk.cli", "run", "--body", body, "--arena", "difficult", "--controller",
           "plastic", "--steps", str(steps), "--quiet", "--overwrite", "--out", str(folder)]  # fmt: skip
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        raise SystemExit(f"run of {steps} steps failed with status {p.returncode}")
    return usage.ru_maxrss / 1024, wall  # ru_maxrss is in KiB on Linux


def measure(body: str, lengths: list[int], tmp: Path) -> dict[str, object]:
    """The runs of one body: a cold 5-step warm-up, then each length; peak RSS over the shortest run's."""
    cold, _ = peak_mb(body, 5, tmp / f"{body}-warm-up")  # compiles the numba kernels into the cache, once
    print(f"{body}:        5 steps: peak {cold:6.1f} MB (cold: compiling the kernels)", flush=True)
    rows = []
    for n in lengths:
        mb, wall = peak_mb(body, n, tmp / f"{body}-{n}")
        rows.append({"steps": n, "peak_rss_mb": round(mb, 1), "wall_s": round(wall, 1)})
        print(f"{body}: {n:>9,} steps: peak {mb:6.1f} MB in {wall:7.1f} s", flush=True)
    base = rows[0]["peak_rss_mb"]
    for r in rows:
        r["over_shortest_mb"] = round(float(r["peak_rss_mb"]) - float(base), 1)
    return {"command": f"neurowalk run --body {body} --arena difficult --controller plastic --steps N",
            "runs": rows, "warm_up_5_steps_cold_cache_mb": round(cold, 1)}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bodies", default="amosii,surrogate", help="comma-separated bodies")
    ap.add_argument("--steps", default="2000,100000,1000000", help="comma-separated run lengths (control steps)")
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    lengths = [int(s) for s in args.steps.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        bodies = {b: measure(b, lengths, Path(tmp)) for b in args.bodies.split(",")}
    args.out.mkdir(parents=True, exist_ok=True)
    result = {"bodies": bodies, "cores": os.cpu_count()}
    (args.out / "memory.json").write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
