"""Judge the committed reproduction (docs/results/ and docs/results/quick/) again by the current rules, from the
runs' committed numbers (no run is repeated), and write its records, report, details, totals and the gallery.

A changed rule is carried into the committed records this way; ``tests/experiments/reproduce/test_committed.py``
holds them to what the current judges say. It prints each claim whose verdict moved, before and after.

Run: ``python tools/rejudge.py``.
"""

from __future__ import annotations

import json
from pathlib import Path

from neurowalk.experiments.reproduce.gallery import gallery
from neurowalk.experiments.reproduce.plan import PLAN
from neurowalk.experiments.reproduce.report import write_report
from neurowalk.experiments.reproduce.runner import rejudged
from neurowalk.fileio import write_json

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "docs" / "results"


def main() -> None:
    """Rejudge both folders; print the moves."""
    for out, quick in ((RESULTS, False), (RESULTS / "quick", True)):
        for item in PLAN:
            path = out / f"{item.name}.json"
            old = json.loads(path.read_text(encoding="utf-8"))
            new = rejudged(item, old, out)
            before = {c["what"]: c["verdict"] for c in old["claims"]}
            for c in new["claims"]:
                if before.get(c["what"]) != c["verdict"]:
                    print(f"{out.name}/{item.name}: {c['what']}: {before.get(c['what'])} -> {c['verdict']}")
            if old["verdict"] != new["verdict"]:
                print(f"{out.name}/{item.name}: result {old['verdict']} -> {new['verdict']}")
            write_json(path, new)
        write_report(out, quick)
    page = ROOT / "docs" / "gallery.md"
    page.write_text(gallery(RESULTS, page), encoding="utf-8")


if __name__ == "__main__":
    main()
