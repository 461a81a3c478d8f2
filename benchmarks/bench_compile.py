"""What the first run of a command costs: numba compiling the kernels it calls, once, into an empty cache.

For each command (the README's first steps: the first run of docs/index.md and ``neurowalk figure table2``), runs
it ``--repeats`` times in a child process with an empty numba cache (a fresh ``NUMBA_CACHE_DIR``), each time
followed by the same command on the cache it filled; the first run's extra wall time, the median cold run's over
the median warm one's, is what compiling the kernels cost. Each run writes into a fresh folder (a figure would
otherwise go on from its finished runs). ``neurowalk.progress.COMPILE_TIME``, the compile note's estimate, is
checked against this file (tests/test_compile_note.py).

Run: ``python benchmarks/bench_compile.py [--repeats 3] [--out out/bench]``; writes ``compile.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: name -> the command's arguments after ``neurowalk`` (``--out`` is added).
COMMANDS = {
    "run": ["run", "--arena", "box", "--controller", "plastic", "--steps", "1500", "--quiet"],
    "table2": ["figure", "table2"],
}


def wall_s(args: list[str], cache: Path, out: Path) -> float:
    """The wall time, s, of ``neurowalk ARGS --out OUT`` in a child process with numba's cache in ``cache``."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "NEUROWALK_COMPILE_NOTE": "0"}
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "neurowalk", *args, "--out", str(out)], env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    return time.perf_counter() - t0


def measure(name: str, args: list[str], repeats: int, tmp: Path) -> dict[str, object]:
    """``repeats`` pairs of a cold run (an empty cache) and a warm one (the cache it filled)."""
    cold, warm = [], []
    for i in range(repeats):
        cache = tmp / f"{name}-cache-{i}"
        cold.append(round(wall_s(args, cache, tmp / f"{name}-cold-{i}"), 1))
        warm.append(round(wall_s(args, cache, tmp / f"{name}-warm-{i}"), 1))
        print(f"{name}: cold {cold[-1]:5.1f} s, warm {warm[-1]:5.1f} s", flush=True)
    cold_s, warm_s = statistics.median(cold), statistics.median(warm)
    return {
        "command": "neurowalk " + " ".join(args),
        "cold_s": cold,
        "warm_s": warm,
        "cold_median_s": cold_s,
        "warm_median_s": warm_s,
        "first_run_extra_s": round(cold_s - warm_s, 1),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3, help="cold and warm runs of each command")
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        commands = {name: measure(name, a, args.repeats, Path(tmp)) for name, a in COMMANDS.items()}
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    result = {
        "commands": commands,
        "cores": os.cpu_count(),
        "commit": commit or None,
        "run_with": f"python benchmarks/bench_compile.py --repeats {args.repeats}",
        "note": "cores shared with other work during the run: the times vary with its load",
    }
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "compile.json").write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
