"""Run the plan of :mod:`.plan`: each figure once (a subprocess, `neurowalk figure FIG --settings FILE`: its typed
settings in a file), each item judged.

Layout of the output folder ``DIR``:

* ``DIR/RUN/``: a figure's own output (``FIG.png``, ``FIG.json``, ``FIG.npz``, its result stores) and ``log.txt``,
  the command's output. ``RUN`` is the name of the first item that uses the run; items that read the same run
  (Table 1's and Fig. 7's share none; the long runs share Fig. 5's) judge the same files.
* ``DIR/RUN/settings.json``: the figure and its settings (:class:`~neurowalk.experiments.Settings` fields), which the
  command reads (``neurowalk figure FIG --settings DIR/RUN/settings.json`` runs it again by hand).
* ``DIR/RUN/command.json``: written after the command succeeded; a later ``reproduce`` skips the run where it
  names the same figure and settings (and otherwise runs it again: the figure's stores keep finished runs).
* ``DIR/NAME.json``: an item's result (:func:`item_record`), written after its run.
* ``DIR/report.md``: the table of all items (:mod:`.report`).

A stop (Ctrl-C, SIGTERM) stops the running figure, which keeps its finished runs in its stores; what is on disk
is what the summary line says. A ``reproduce`` killed outright (SIGKILL) takes its figure with it: the kernel sends
the figure SIGTERM, and it stops as on Ctrl-C.
"""

from __future__ import annotations

import functools
import json
import os
import platform
import shlex
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from neurowalk import profiling
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.reproduce.causes import with_causes
from neurowalk.experiments.reproduce.claims import overall
from neurowalk.experiments.reproduce.judge_authors import compare
from neurowalk.experiments.reproduce.plan import Item
from neurowalk.fileio import write_json
from neurowalk.profiling import read_profile
from neurowalk.runners.local import die_with_parent

#: The folder in ``DIR/RUN`` the figure's processes write their profiles into (:mod:`neurowalk.profiling`).
PROFILE = "profile"
#: The folder in ``DIR`` of the result stores all figures of a reproduction share (``Settings.shared_runs``).
SHARED_RUNS = "runs"
#: The file in ``DIR/RUN`` of the figure's settings, which its command reads.
SETTINGS_FILE = "settings.json"


@dataclass(frozen=True)
class Run:
    """One figure and its settings: the items judged from it share its folder ``DIR/name``.

    Attributes:
        name: the folder's name (the first item's). figure: the figure (:data:`~neurowalk.experiments.FIGURES`).
        given: its settings by field name (JSON-able; out and shared_runs are the reproduction's).
    """

    name: str
    figure: str
    given: tuple[tuple[str, Any], ...]

    def settings(self, out: Path) -> Settings:
        """Its typed settings in the reproduction ``out``: its own folder ``DIR/name`` and the shared stores
        ``DIR/runs`` (a run two figures need is made once)."""
        return Settings(**dict(self.given), out=out / self.name, shared_runs=out / SHARED_RUNS)

    def settings_file(self, out: Path) -> dict[str, Any]:
        """What ``DIR/RUN/settings.json`` holds: the figure and its settings (paths as text)."""
        s = self.settings(out)
        return {
            "figure": self.figure,
            "settings": {**dict(self.given), "out": str(s.out), "shared_runs": str(s.shared_runs)},
        }

    def command(self, out: Path) -> list[str]:
        """The command's words, as a user types them: ``neurowalk figure FIG --settings DIR/RUN/settings.json``."""
        return ["neurowalk", "figure", self.figure, "--settings", str(out / self.name / SETTINGS_FILE)]


def runs_of(items: list[Item], quick: bool, workers: int | None) -> tuple[list[Run], dict[str, Run]]:
    """The distinct figures and settings of ``items`` in order, and each item's run (by item name); ``workers`` goes
    to the figures that take it."""
    runs: dict[tuple[str, tuple[tuple[str, Any], ...]], Run] = {}
    of: dict[str, Run] = {}
    for item in items:
        given = item.given(quick)
        if workers is not None and "workers" in FIGURES[item.figure].takes:
            given["workers"] = workers
        key = (item.figure, tuple(sorted(given.items())))
        if key not in runs:
            runs[key] = Run(item.name, item.figure, key[1])
        of[item.name] = runs[key]
    return list(runs.values()), of


def versions() -> dict[str, str]:
    """Versions of what a result depends on, the machine, and its CPU as the numbers see it (the same seed gives the
    same bits where these are the same: :mod:`neurowalk.cpu`)."""
    import matplotlib
    import mujoco
    import numba
    import numpy

    from neurowalk import __version__
    from neurowalk.cpu import cpu_fingerprint

    return {
        "neurowalk": __version__,
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "mujoco": mujoco.__version__,
        "numba": numba.__version__,
        "matplotlib": matplotlib.__version__,
        "machine": f"{platform.system()} {platform.machine()}, {os.cpu_count()} cores",
        "cpu": ", ".join(f"{k} {' '.join(v) if isinstance(v, list) else v}" for k, v in cpu_fingerprint().items()),
    }


def done(run: Run, out: Path) -> dict[str, Any] | None:
    """The record of ``run``'s finished command in ``out`` (None where it has not finished with these settings)."""
    path = out / run.name / "command.json"
    try:
        rec = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    ok = isinstance(rec, dict) and rec.get("figure") == run.figure and rec.get("settings") == dict(run.given)
    return rec if ok and (out / run.name / f"{run.figure}.json").is_file() else None


class RunFailedError(RuntimeError):
    """A figure command exited with an error; names the command, its status and its log."""


def execute(run: Run, out: Path, tick: Any = None) -> dict[str, Any]:
    """Run ``run``'s command (its output into ``DIR/RUN/log.txt``); its record (command, wall time, versions).

    ``tick(elapsed_s)`` is called about twice a second while it runs (the progress display). A stop (SIGINT or
    SIGTERM here) is passed on to the command, which keeps its finished runs; then KeyboardInterrupt.
    """
    folder = out / run.name
    folder.mkdir(parents=True, exist_ok=True)
    write_json(folder / SETTINGS_FILE, run.settings_file(out))
    # an earlier command started and did not finish (its log is there): the figure goes on from the runs it stored,
    # and its wall time is what was left to run
    resumed = (folder / "log.txt").is_file()
    words = run.command(out)
    profile = folder / PROFILE
    shutil.rmtree(profile, ignore_errors=True)  # this command's processes alone
    t0 = time.perf_counter()
    with open(folder / "log.txt", "wb") as log:
        proc = subprocess.Popen(
            [sys.executable, "-m", "neurowalk", *words[1:]],
            stdout=log,
            stderr=subprocess.STDOUT,
            env={**os.environ, profiling.ENV: str(profile)},
            preexec_fn=functools.partial(die_with_parent, os.getpid(), signal.SIGTERM),  # stops cleanly with us
        )
        try:
            while proc.poll() is None:
                try:
                    proc.wait(timeout=0.5)
                except subprocess.TimeoutExpired:
                    if tick is not None:
                        tick(time.perf_counter() - t0)
        except KeyboardInterrupt:
            proc.send_signal(signal.SIGINT)
            proc.wait()
            raise
    wall = time.perf_counter() - t0
    if proc.returncode in (130, 143):  # the command was stopped (by our SIGINT, or by a SIGTERM): so is this one
        raise KeyboardInterrupt
    if proc.returncode != 0:
        raise RunFailedError(f"`{shlex.join(words)}` exited with status {proc.returncode}; see {folder / 'log.txt'}")
    record = {
        "command": shlex.join(words),
        "figure": run.figure,
        "settings": dict(run.given),
        "wall_time_s": round(wall, 1),
        "resumed": resumed,  # then wall_time_s is what was left to run, not the figure's time
        "profile": read_profile(profile, round(wall, 1)),
        "versions": versions(),
    }
    write_json(folder / "command.json", record)
    return record


def item_record(item: Item, run: Run, record: dict[str, Any], out: Path, quick: bool) -> dict[str, Any]:
    """An item's result: its command, versions, seeds, wall time, claims and verdict, judged from the run's json, and
    where the authors' simulator has runs of it, ``authors``: their claims and numbers beside neurowalk's."""
    summary = json.loads((out / run.name / f"{run.figure}.json").read_text(encoding="utf-8"))
    return {
        "name": item.name,
        "paper": item.paper,
        "figure": run.figure,
        "quick": quick,
        "command": record["command"],
        "settings": record["settings"],
        "wall_time_s": record["wall_time_s"],
        "resumed": bool(record.get("resumed", False)),
        "profile": record.get("profile"),
        "versions": record["versions"],
        "seed": dict(run.given).get("seed", 0),
        "seeds": summary.get("seeds"),
        "control_hz": summary.get("control_hz", 10.0),
        "files": {
            "png": f"{run.name}/{run.figure}.png",
            "json": f"{run.name}/{run.figure}.json",
        },
        **_judged(item, summary, quick, out),
    }


def _judged(item: Item, summary: dict[str, Any], quick: bool, out: Path) -> dict[str, Any]:
    """``item``'s claims (with their causes), verdict and reason from the figure's ``summary``, and ``authors``: the
    authors' simulator beside neurowalk (:func:`.judge_authors.compare`), where its runs answer some of the item."""
    claims = with_causes(item.name, item.judge(summary, quick), summary, out)
    verdict, reason = overall(claims)
    entry = compare(item.name, summary, claims)
    judged = {"claims": [c.to_json() for c in claims], "verdict": verdict, "reason": reason}
    return judged if entry is None else {**judged, "authors": entry}


def rejudged(item: Item, record: dict[str, Any], out: Path) -> dict[str, Any]:
    """``item``'s written ``record`` (``DIR/NAME.json``) with its claims, verdict and reason judged again by the
    current code from the run's numbers in ``out`` (the run itself is not repeated): what a changed judge says; its
    ``authors`` entry made again too."""
    summary = json.loads((out / record["files"]["json"]).read_text(encoding="utf-8"))
    rest = {k: v for k, v in record.items() if k != "authors"}
    return {**rest, **_judged(item, summary, record["quick"], out)}


def write_item(item: Item, run: Run, record: dict[str, Any], out: Path, quick: bool) -> Path:
    """Judge ``item`` from its finished run and write ``DIR/NAME.json``; its path."""
    path = out / f"{item.name}.json"
    write_json(path, item_record(item, run, record, out, quick))
    return path


def summary_line(out: Path, quick: bool, report: Path, wall: float) -> str:
    """The closing line: how many results were reproduced, partly and not, and where the report is."""
    from neurowalk.experiments.reproduce.report import read_records

    records = read_records(out, quick).values()
    counts = ", ".join(f"{sum(r['verdict'] == v for r in records)} {v}" for v in ("reproduced", "partly", "not"))
    return f"reproduce: {len(records)} results ({counts}) in {wall:.0f} s; wrote {report}"
