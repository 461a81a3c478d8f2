"""How far results differ between CPUs: two runs of the same command compared number by number.

The same seed on the same CPU type gives the same bits; on another CPU numba compiles for another target, numpy
picks other SIMD kernels and its OpenBLAS other kernels, so some last bits differ. This compares

* two ``neurowalk reproduce --quick`` folders (``--reproduce A B``): each result's verdict and every claim's
  measured value, and every number of each figure's json (floats: how many differ, the largest absolute and
  relative difference; every other value: the paths that differ);
* two ``python tests/regression/record.py --out DIR`` folders (``--regression A B``): which case hashes differ,
  which outcomes, and the largest difference of the heads.

The second machine can be emulated on this one (what ``docs/usage.md`` reports)::

    NUMBA_CPU_NAME=znver3 OPENBLAS_CORETYPE=Zen NPY_DISABLE_CPU_FEATURES="X86_V4 AVX512_ICL AVX512_SPR" \\
        neurowalk reproduce --quick --out out/repro-other

Run: ``python benchmarks/cross_cpu.py --reproduce out/repro-host out/repro-other --regression A B --emulated
"..." --out docs/benchmarks/cross_cpu.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
from pathlib import Path
from typing import Any

import numpy as np

#: Keys that measure the machine or name a folder, not the result.
VOLATILE = ("wall", "time_s", "real_time_factor", "store", "files", "command", "versions", "resumed")


def _leaves(v: Any, path: str = "") -> dict[str, Any]:
    """path -> leaf value of a JSON document (lists indexed), the volatile keys left out."""
    if isinstance(v, dict):
        out: dict[str, Any] = {}
        for k, x in v.items():
            if not any(word in k for word in VOLATILE):
                out.update(_leaves(x, f"{path}/{k}"))
        return out
    if isinstance(v, list):
        out = {}
        for i, x in enumerate(v):
            out.update(_leaves(x, f"{path}/{i}"))
        return out
    return {path: v}


def compare_json(a: Any, b: Any) -> dict[str, Any]:
    """Floats of ``a`` and ``b`` by path: how many, how many differ, the largest differences; other values: the
    paths where they differ (or where only one document has a value)."""
    la, lb = _leaves(a), _leaves(b)
    both_float = {p for p in la if p in lb and isinstance(la[p], float) and isinstance(lb[p], float)}
    floats = [(la[p], lb[p]) for p in sorted(both_float)]
    other = sorted(p for p in set(la) | set(lb) if p not in both_float and la.get(p, ...) != lb.get(p, ...))
    diffs = [(abs(x - y), abs(x - y) / max(abs(x), abs(y))) for x, y in floats
             if x != y and not (math.isnan(x) and math.isnan(y))]  # fmt: skip
    return {
        "floats": len(floats),
        "floats_differing": len(diffs),
        "max_abs_diff": max((d[0] for d in diffs), default=0.0),
        "max_rel_diff": max((d[1] for d in diffs), default=0.0),
        "other_values_differing": other,
    }


def compare_reproduce(a: Path, b: Path) -> dict[str, Any]:
    """Every result both folders measured: verdicts, claims and the figure's numbers."""
    out: dict[str, Any] = {}
    for rec in sorted(a.glob("*.json")):
        if rec.name == "reproduce.json" or not (b / rec.name).is_file():
            continue
        ra, rb = json.loads(rec.read_text()), json.loads((b / rec.name).read_text())
        name = rec.stem
        fa, fb = a / name / f"{name}.json", b / name / f"{name}.json"
        out[name] = {
            "verdicts": [ra["verdict"], rb["verdict"]],
            "claims": compare_json(ra["claims"], rb["claims"]),
            "figure": compare_json(json.loads(fa.read_text()), json.loads(fb.read_text())) if fa.is_file() else None,
        }
    return out


def compare_regression(a: Path, b: Path) -> dict[str, Any]:
    """Two records of the regression list: hashes and outcomes that differ, the largest difference of the heads."""
    ja, jb = json.loads((a / "hashes.json").read_text()), json.loads((b / "hashes.json").read_text())
    with np.load(a / "heads.npz", allow_pickle=False) as za, np.load(b / "heads.npz", allow_pickle=False) as zb:
        worst = 0.0
        for k in za.files:
            d = np.abs(za[k] - zb[k])
            worst = max(worst, float(np.max(d[np.isfinite(d)], initial=0.0)))
    return {
        "fingerprints": [ja["fingerprint"], jb["fingerprint"]],
        "cases": len(ja["hashes"]),
        "hashes_differing": sorted(k for k in ja["hashes"] if ja["hashes"][k] != jb["hashes"][k]),
        "hashes_differing_count": sum(ja["hashes"][k] != jb["hashes"][k] for k in ja["hashes"]),
        "outcomes_differing": sorted(k for k in ja["outcomes"] if ja["outcomes"][k] != jb["outcomes"][k]),
        "heads_max_abs_diff": worst,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reproduce", nargs=2, type=Path, metavar=("HOST", "OTHER"))
    ap.add_argument("--regression", nargs=2, type=Path, metavar=("HOST", "OTHER"))
    ap.add_argument("--emulated", default="", help="the settings that made OTHER (recorded in the output)")
    ap.add_argument("--out", type=Path, default=Path("out/bench/cross_cpu.json"))
    args = ap.parse_args()
    result: dict[str, Any] = {"machine": platform.platform(), "other": args.emulated}
    if args.reproduce:
        per = compare_reproduce(*args.reproduce)
        result["reproduce_quick"] = per
        result["reproduce_totals"] = {
            "results": len(per),
            "verdicts_differing": sorted(k for k, r in per.items() if r["verdicts"][0] != r["verdicts"][1]),
            "results_with_other_values_differing": sorted(
                k
                for k, r in per.items()
                if r["claims"]["other_values_differing"] or (r["figure"] and r["figure"]["other_values_differing"])
            ),
            "floats": sum(r["claims"]["floats"] + (r["figure"] or {}).get("floats", 0) for r in per.values()),
            "floats_differing": sum(
                r["claims"]["floats_differing"] + (r["figure"] or {}).get("floats_differing", 0) for r in per.values()
            ),
            "max_rel_diff": max(
                max(r["claims"]["max_rel_diff"], (r["figure"] or {}).get("max_rel_diff", 0.0)) for r in per.values()
            ),
        }
        totals = result["reproduce_totals"]
        totals["verdicts_differing_count"] = len(totals["verdicts_differing"])
        totals["max_rel_diff_ulps"] = totals["max_rel_diff"] / np.finfo(float).eps  # units in the last place
    if args.regression:
        result["regression"] = compare_regression(*args.regression)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps(result.get("reproduce_totals", {}), indent=1))
    if "regression" in result:
        r = result["regression"]
        print(f"regression: {len(r['hashes_differing'])} of {r['cases']} hashes differ, outcomes differing "
              f"{r['outcomes_differing']}, heads within {r['heads_max_abs_diff']:.1e}")  # fmt: skip
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
