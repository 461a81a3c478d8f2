"""Two full reproductions on two machines, side by side: each figure command's wall time, and what changed.

A reproduction's times are its machine's. To tell a change of the code from a change of the machine, this compares
two ``neurowalk reproduce`` folders figure by figure: each command's wall time in both, whether its result is the
same (every claim's measured value and verdict equal), and the machine factor: the median ratio of the times of
the figures whose results are the same and whose runs the change did not touch (``--changed``). The total of the
second reproduction divided by that factor is its time at the first machine's speed.

Run: ``python benchmarks/reproduction_times.py BEFORE AFTER [--out FILE]`` (default
``docs/benchmarks/reproduction_times.json``), e.g. the committed ``docs/results`` of an earlier commit (``git
archive``) against a new ``out/reproduce``.
"""

from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path
from typing import Any

from neurowalk.fileio import write_json


def _record(folder: Path, name: str) -> dict[str, Any]:
    return json.loads((folder / f"{name}.json").read_text(encoding="utf-8"))


def _claims(record: dict[str, Any]) -> list[tuple[Any, str]]:
    return [(c["measured"], c["verdict"]) for c in record["claims"]]


def compare(
    before: Path, after: Path, changed: tuple[str, ...] = (), labels: tuple[str, str] = ("", "")
) -> dict[str, Any]:
    """Per figure command: its wall time in both, and whether the results it gave are the same; the factor, from the
    figures whose results are the same and that the change did not touch (``changed``: figure names)."""
    figures: dict[str, Any] = {}
    for path in sorted(after.glob("*/command.json")):
        name = path.parent.name
        if not (before / name / "command.json").is_file():
            continue
        records = [p.stem for p in after.glob("*.json") if p.stem != "reproduce" and _record(after, p.stem)
                   ["files"]["json"].split("/")[0] == name]  # fmt: skip
        same = all(_claims(_record(before, r)) == _claims(_record(after, r)) for r in records)
        t0 = json.loads((before / name / "command.json").read_text())["wall_time_s"]
        t1 = json.loads(path.read_text())["wall_time_s"]
        figures[name] = {"before_s": t0, "after_s": t1, "ratio": t1 / t0, "same_results": same, "results": records,
                         "changed": name in changed or not same}  # fmt: skip
    same = [f["ratio"] for f in figures.values() if not f["changed"]]
    factor = statistics.median(same)
    total0 = sum(f["before_s"] for f in figures.values())
    total1 = sum(f["after_s"] for f in figures.values())
    return {
        "what": __doc__.splitlines()[0],
        "before": labels[0] or str(before),
        "after": labels[1] or str(after),
        "figures": figures,
        "unchanged_figures": len(same),
        "machine_factor": factor,
        "machine_factor_range": [min(same), max(same)],
        "changed": [n for n, f in figures.items() if f["changed"]],
        "total_before_s": total0,
        "total_after_s": total1,
        "total_after_at_before_speed_s": total1 / factor,
        "changed_before_s": sum(f["before_s"] for f in figures.values() if f["changed"]),
        "changed_after_at_before_speed_s": sum(f["after_s"] for f in figures.values() if f["changed"]) / factor,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--changed", default="", help="figures the change touched (comma-separated): not in the factor")
    ap.add_argument("--labels", nargs=2, default=("", ""), help="what BEFORE and AFTER are, in words")
    ap.add_argument("--out", type=Path, default=Path("docs/benchmarks/reproduction_times.json"))
    args = ap.parse_args()
    out = compare(args.before, args.after, tuple(n for n in args.changed.split(",") if n), tuple(args.labels))
    for name, f in out["figures"].items():
        mark = ("" if f["same_results"] else "  results changed") + ("  (changed)" if f["changed"] else "")
        print(f"{name:15s} {f['before_s']:7.1f} s -> {f['after_s']:7.1f} s ({f['ratio']:.2f}x){mark}")
    at = out["total_after_at_before_speed_s"]
    print(f"machine factor {out['machine_factor']:.3f}; total {out['total_before_s']:.0f} s -> "
          f"{out['total_after_s']:.0f} s ({at:.0f} s at the first one's speed)")  # fmt: skip
    write_json(args.out, out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
