"""Record the regression list's hashes into ``hashes.json`` (only where a change of results is intended).

Run: ``python tests/regression/record.py`` from the project root.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

sys.path.insert(0, str(Path(__file__).parent))

from cases import CASES, fingerprint


def main() -> None:
    hashes = {}
    for name, case in CASES.items():
        with tempfile.TemporaryDirectory() as tmp:
            hashes[name] = case(Path(tmp))
        plt.close("all")
        print(f"{name}: {hashes[name]}", flush=True)
    out = Path(__file__).with_name("hashes.json")
    out.write_text(json.dumps({"fingerprint": fingerprint(), "hashes": hashes}, indent=2) + "\n")
    print(f"wrote {out} ({len(hashes)} cases)")


if __name__ == "__main__":
    main()
