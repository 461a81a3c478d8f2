"""Record the regression list's hashes, outcomes and heads (only where a change of results is intended).

Run: ``python tests/regression/record.py`` from the project root: writes ``hashes.json`` and ``heads.npz`` beside
this file. ``--out DIR`` writes them into DIR instead (to compare a machine, or a CPU target, with the record).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from cases import CASES, fingerprint


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path(__file__).parent)
    ap.add_argument("cases", nargs="*", help="record these cases only (default: all)")
    args = ap.parse_args()
    hashes, outcomes, heads = {}, {}, {}
    for name in args.cases or CASES:
        with tempfile.TemporaryDirectory() as tmp:
            result = CASES[name](Path(tmp))
        plt.close("all")
        hashes[name], outcomes[name] = result.sha256, result.outcome
        heads.update({f"{name}|{key}": a for key, a in result.head.items()})
        print(f"{name}: {result.sha256}", flush=True)
    args.out.mkdir(parents=True, exist_ok=True)
    record = {"fingerprint": fingerprint(), "hashes": hashes, "outcomes": outcomes}
    (args.out / "hashes.json").write_text(json.dumps(record, indent=2) + "\n")
    np.savez_compressed(args.out / "heads.npz", **heads)
    print(f"wrote {args.out / 'hashes.json'} and heads.npz ({len(hashes)} cases)")


if __name__ == "__main__":
    main()
