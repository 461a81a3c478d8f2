"""Closed loop vs bare ``mj_step`` on the same model for the same simulated time, side by side.

The baseline replays the closed loop's own recorded joint targets open-loop (so the robot makes
the same motions and contacts) with nothing but ``data.ctrl[:] = ...; mj_step(nstep)`` per
control step. The closed loop adds sensors, noise, the neural controller and recording.
The measurement is :func:`neurowalk.experiments.bench.closed_loop_ratio` (also in ``neurowalk bench``'s bench.json).

Run: ``python benchmarks/bench_closed_loop.py [--steps 3000] [--out out/bench]``; writes
``closed_loop.json``. Reported: median wall time of each over repeats (interleaved), their ratio
(the budget is 1.10), and real-time factors.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from neurowalk.experiments.bench import closed_loop_ratio


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args()
    report = closed_loop_ratio(args.steps, args.repeats)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "closed_loop.json").write_text(json.dumps(report, indent=2) + "\n")
    print(f"bare mj_step   {report['bare_mj_step_wall_s']:7.3f} s  ({report['real_time_factor_bare']:.0f}x real time)")
    print(f"closed loop    {report['closed_loop_wall_s']:7.3f} s  ({report['real_time_factor_closed_loop']:.0f}x "
          f"real time, {report['control_steps_per_s_closed_loop']:.0f} control steps/s)")  # fmt: skip
    print(f"ratio          {report['ratio_closed_loop_over_bare']:.3f} (budget 1.10)")


if __name__ == "__main__":
    main()
