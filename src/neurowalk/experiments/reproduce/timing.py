"""How long each figure takes, from the committed reproduction (``docs/results/`` and ``docs/results/quick/``).

:data:`TIMES` (``figure_times.json`` beside this module) holds, per figure, the wall time of its default command
(``neurowalk figure FIG`` and with ``--quick``) in the committed runs, and the machine they ran on;
:func:`measured_times` makes it from the two runs' ``command.json`` files (a test holds the two in step).
``neurowalk figure list`` shows the times; ``neurowalk reproduce`` weighs its progress display by them.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

TIMES = Path(__file__).with_name("figure_times.json")
#: Expected seconds of a figure with no committed time (a new figure): quick, full.
UNKNOWN = (60.0, 600.0)


def figure_times() -> dict[str, Any]:
    """The committed times: ``{"machine": str, "figures": {FIG: {"quick_s": float|None, "full_s": float|None}}}``
    (empty figures where the file is missing)."""
    try:
        data = json.loads(TIMES.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {"machine": None, "figures": {}}
    return data if isinstance(data, dict) and isinstance(data.get("figures"), dict) else {"figures": {}}


def expected_seconds(figure: str, quick: bool) -> float:
    """Seconds ``neurowalk figure FIG`` (``--quick`` if ``quick``) took in the committed run (a guess if none)."""
    t = figure_times()["figures"].get(figure, {}).get("quick_s" if quick else "full_s")
    return float(t) if isinstance(t, int | float) else UNKNOWN[0 if quick else 1]


def measured_times(full: Path, quick: Path) -> dict[str, Any]:
    """The times file's content from a full and a quick reproduction's output folders: per figure, the wall time
    of the run of its default command (the run named as the figure), and the machine of the full run."""
    figures: dict[str, dict[str, float | None]] = {}
    machine = None
    for key, folder in (("full_s", full), ("quick_s", quick)):
        for path in sorted(Path(folder).glob("*/command.json")):
            rec = json.loads(path.read_text(encoding="utf-8"))
            figure = rec["command"].split()[2]
            if path.parent.name != figure or rec.get("resumed"):  # other flags; or the time of a part only
                continue
            figures.setdefault(figure, {"quick_s": None, "full_s": None})[key] = rec["wall_time_s"]
            if key == "full_s" or machine is None:
                machine = rec["versions"]["machine"]
    return {"machine": machine, "figures": dict(sorted(figures.items()))}


def describe(figure: str) -> str:
    """``"quick 40 s, full 12 min"`` for ``figure list`` ("" where nothing is committed)."""
    t = figure_times()["figures"].get(figure)
    if not t:
        return ""
    parts = [f"{k} {_span(t[f'{k}_s'])}" for k in ("quick", "full") if t.get(f"{k}_s") is not None]
    return ", ".join(parts)


def _span(seconds: float) -> str:
    """``"40 s"``, ``"12 min"``, ``"1.5 h"``."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
