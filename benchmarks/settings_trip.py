"""The settings' trip through the code: follow a figure's settings from `neurowalk figure`'s arguments to its files
(and a run's, from `neurowalk run`'s).

Runs ``neurowalk figure NAME --quick`` in this process under a profiler that records each function of neurowalk's own
code that receives the settings: the command line's parsed arguments (``cmd_figure``'s ``args``), a
:class:`~neurowalk.experiments.Settings`, or what the driver makes of them (a run's ``EpisodeConfig``, the settings
applied, or a list of them; the output folder or a file in it, such as the result store) as an argument (a method
of the object itself, ``self``, is where it lives, not a trip). A function counts at its first such call (the same
function called again, for each of a study's runs, is the same road; so is a generator's resumption). Consecutive
functions in one file make one **stay**; a stay in a higher layer than the stay before it (DESIGN.md §4's order, as
``tests/test_layers.py`` holds it) **climbs back up**; a stay in a file the trip had left
before **returns** to it. The runs themselves (in the pool's workers) are not followed.

    python benchmarks/settings_trip.py [--figures fig2 fig4 table2 fig8 run] [--out docs/benchmarks/settings_trip.json]
"""

from __future__ import annotations

import argparse
import itertools
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import ValuesView
from pathlib import Path
from types import CodeType, FrameType
from typing import Any

import matplotlib

matplotlib.use("Agg")
if not os.environ.get("DISPLAY"):  # as the command does before MuJoCo loads: offscreen snapshots (fig8)
    os.environ.setdefault("MUJOCO_GL", "egl")

import neurowalk
from neurowalk.cli import main
from neurowalk.experiments import Settings
from neurowalk.fileio import write_json
from neurowalk.sim.config import EpisodeConfig

PKG = Path(neurowalk.__file__).parent
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from test_layers import LAYERS  # noqa: E402


def layer(file: str) -> int:
    """The layer of a file of the package, given relative to it (its top-level module or subpackage)."""
    top = Path(file).parts[0].removesuffix(".py")
    return next(i for i, names in enumerate(LAYERS) if top in names)


#: The run the trip of ``run`` follows: a short physics run.
RUN = ["run", "--arena", "box", "--steps", "200", "--quiet"]


def argv(name: str, out: Path) -> list[str]:
    """The command line followed: ``neurowalk figure NAME --quick``, or for ``run`` :data:`RUN`."""
    return [*RUN, "--out", str(out)] if name == "run" else ["figure", name, "--quick", "--out", str(out)]


def trip(figure: str, out: Path) -> list[tuple[str, str]]:
    """(file, function) of every call of neurowalk's code that receives the settings of ``neurowalk figure FIGURE
    --quick`` (``run``: of :data:`RUN`), in order."""
    calls: list[tuple[str, str]] = []
    seen: set[CodeType] = set()  # the functions on the trip so far

    def carries(value: Any) -> bool:
        """The settings, or what the driver makes of them: a run's config (the settings applied), the output
        folder or a file in it (the result store)."""
        if isinstance(value, Settings | argparse.Namespace | EpisodeConfig):
            return True
        if isinstance(value, list | tuple | ValuesView) and value:  # a dict's values too (the store's configs)
            return carries(next(iter(value)))
        return isinstance(value, Path) and (value == out or out in value.parents)

    def profile(frame: FrameType, event: str, arg: Any) -> None:
        if event != "call":
            return
        file = frame.f_code.co_filename
        if not file.startswith(str(PKG)):
            return
        n = frame.f_code.co_argcount + frame.f_code.co_kwonlyargcount
        names = [a for a in frame.f_code.co_varnames[:n] if a != "self"]  # its own methods: where it lives
        if any(carries(frame.f_locals.get(a)) for a in names) and frame.f_code not in seen:
            seen.add(frame.f_code)
            calls.append((str(Path(file).relative_to(PKG)), frame.f_code.co_name))

    sys.setprofile(profile)
    try:
        status = main(argv(figure, out))
    finally:
        sys.setprofile(None)
    if status != 0:
        raise RuntimeError(f"{' '.join(argv(figure, out))} exited {status}")
    return calls


def measure(calls: list[tuple[str, str]]) -> dict[str, Any]:
    """The trip's stays, climbs back up and returns, and the stays themselves."""
    stays: list[dict[str, Any]] = []
    for file, fn in calls:
        if stays and stays[-1]["file"] == file:
            stays[-1]["functions"].append(fn)
        else:
            stays.append({"file": file, "layer": layer(file), "functions": [fn]})
    climbs = sum(b["layer"] > a["layer"] for a, b in itertools.pairwise(stays))
    returns = sum(s["file"] in {t["file"] for t in stays[:k]} for k, s in enumerate(stays))
    for s in stays:
        s["functions"] = list(dict.fromkeys(s["functions"]))
    return {
        "stays": len(stays),
        "files": len({s["file"] for s in stays}),
        "climbs_back_up": climbs,
        "returns": returns,
        "trip": [f"{s['file']} (layer {s['layer']}): {', '.join(s['functions'])}" for s in stays],
    }


def run(figures: list[str]) -> dict[str, Any]:
    """Each figure's trip with ``--quick``, and the most of each count over them."""
    head = subprocess.run(["git", "-C", str(PKG), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    command = f"neurowalk figure NAME --quick; for run: neurowalk {' '.join(RUN)}"
    out: dict[str, Any] = {"command": command, "code": head.stdout.strip(), "figures": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for name in figures:
            t0 = time.perf_counter()
            out["figures"][name] = measure(trip(name, Path(tmp) / name))
            print(f"{name}: {out['figures'][name]['stays']} stays, {out['figures'][name]['climbs_back_up']} climbs "
                  f"back up ({time.perf_counter() - t0:.0f} s)", flush=True)  # fmt: skip
    for key in ("stays", "climbs_back_up", "returns", "files"):
        out[f"most_{key}"] = max(f[key] for f in out["figures"].values())
    out["aim"] = {"stays": 20, "climbs_back_up": 4}
    return out


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--figures", nargs="+", default=["fig2", "fig4", "table2", "fig8", "run"])
    p.add_argument("--out", type=Path, default=Path("docs/benchmarks/settings_trip.json"))
    a = p.parse_args()
    write_json(a.out, run(a.figures))
    print(f"wrote {a.out}")
