"""`neurowalk figure fig3` stopped by SIGINT keeps its finished runs, says how many (what its stores hold), and the
same command again goes on from them to the numbers of an uninterrupted run.

fig3 --quick at a small size (dead ends of 150 control steps, long runs of 200, two dead-end variants, two seeds):
the same code path as the full figure, in seconds.
"""

from __future__ import annotations

import json
import os
import re
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from neurowalk.cli import main
from neurowalk.experiments.suites import deadends

SMALL = """
import sys
from neurowalk.experiments.suites import deadends
deadends.TRAP_STEPS = 150
deadends.QUICK_LONG_STEPS = 200  # long_runs' constant, as deadends.runs reads it
deadends.VARIANTS = {k: deadends.VARIANTS[k] for k in ("simple-deadlock", "narrow-passage")}
from neurowalk.cli import main
sys.exit(main(sys.argv[1:]))
"""
ARGS = ["figure", "fig3", "--quick", "--seeds", "2"]
LINE = re.compile(r"^neurowalk: fig3 interrupted: (\d+) finished runs are kept in (\S+) \((.*)\); run the same "
                  r"command again to go on from them$")  # fmt: skip
MACHINE = ("wall_time_s", "real_time_factor")


@pytest.fixture
def small(monkeypatch):
    monkeypatch.setattr(deadends, "TRAP_STEPS", 150)
    monkeypatch.setattr(deadends, "QUICK_LONG_STEPS", 200)  # long_runs' constant, as deadends.runs reads it
    monkeypatch.setattr(deadends, "VARIANTS", {k: deadends.VARIANTS[k] for k in ("simple-deadlock", "narrow-passage")})


def _count(db: Path) -> int:
    try:
        con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
    except sqlite3.Error:
        return 0
    try:
        return int(con.execute("SELECT count(*) FROM runs WHERE status = 'ok'").fetchone()[0])
    except sqlite3.Error:
        return 0
    finally:
        con.close()


def _finished_at(out: Path) -> dict[str, str]:
    out_rows = {}
    for db in out.glob("*.sqlite"):
        con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
        try:
            out_rows.update({f"{db.name}/{k}": t for k, t in con.execute("SELECT key, finished_at FROM runs")})
        finally:
            con.close()
    return out_rows


def _numbers(out: Path) -> tuple[object, dict[str, np.ndarray]]:
    def strip(x: object) -> object:
        if isinstance(x, dict):
            return {k: strip(v) for k, v in x.items() if k not in MACHINE}
        return [strip(v) for v in x] if isinstance(x, list) else x

    with np.load(out / "fig3.npz") as z:
        arrays = {k: z[k] for k in z.files}
    return strip(json.loads((out / "fig3.json").read_text())), arrays


def _interrupt(out: Path, store: str, rows: int) -> str:
    """Run the small fig3 in a process of its own; SIGINT once ``store`` holds ``rows`` runs; its stderr line."""
    cmd = [sys.executable, "-c", SMALL, *ARGS, "--out", str(out)]
    proc = subprocess.Popen(cmd, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while proc.poll() is None and _count(out / store) < rows and time.monotonic() < deadline:
        time.sleep(0.01)
    assert proc.poll() is None, f"fig3 ended before {rows} runs were in {store}"
    os.killpg(proc.pid, signal.SIGINT)  # as a terminal's Ctrl-C: the figure and its workers
    _, err = proc.communicate(timeout=10)
    assert proc.returncode == 130, err
    lines = [line for line in err.splitlines() if line.startswith("neurowalk")]  # (the progress bars aside)
    assert len(lines) == 1, err
    return lines[0]


def test_an_interrupted_fig3_keeps_its_runs_and_the_rerun_gives_the_uninterrupted_numbers(tmp_path, small):
    assert main([*ARGS, "--out", str(tmp_path / "whole")]) == 0
    whole = _numbers(tmp_path / "whole")
    out = tmp_path / "stopped"
    tables = 2 * len(deadends.NETWORKS) * 2  # the outcome table's runs: 2 dead ends, 4 networks, 2 seeds
    for rows in (4, tables + 1):  # amid the outcome table; amid the example runs
        line = _interrupt(out, "results.sqlite", rows)
        m = LINE.match(line)
        assert m is not None, line
        on_disk = {p.name: _count(p) for p in out.glob("*.sqlite") if _count(p)}
        assert int(m.group(1)) == sum(on_disk.values()) >= rows and m.group(2) == str(out), line
        assert m.group(3) == ", ".join(f"{n} in {name}" for name, n in sorted(on_disk.items())), line
        assert not (out / "fig3.json").exists()
    kept = _finished_at(out)
    assert main([*ARGS, "--out", str(out)]) == 0
    after = _finished_at(out)
    assert len(kept) >= tables + 1 and all(after[k] == t for k, t in kept.items())  # went on from them: none rerun
    again = _numbers(out)
    assert again[0] == whole[0]
    assert again[1].keys() == whole[1].keys() and all(np.array_equal(again[1][k], whole[1][k]) for k in whole[1])
    assert _count(out / "results.sqlite") == tables + 4  # and two example runs, two long runs


@pytest.mark.parametrize(("name", "store_rows", "says"), [
    ("fig7", 0, "fig7 interrupted before any of its runs finished; nothing is kept"),
    ("fig6", 0, "fig6 interrupted before any of its runs finished; nothing is kept"),
    ("fig6", 3, "fig6 interrupted: 3 finished runs are kept in"),
])  # fmt: skip
def test_the_line_of_an_interrupted_figure_is_what_its_folder_holds(name, store_rows, says, tmp_path, monkeypatch,
                                                                    capsys):  # fmt: skip
    from neurowalk.experiments import FIGURES, Settings, study_runs
    from neurowalk.experiments.study import planned
    from neurowalk.runners.store import ResultStore

    if store_rows:
        runs = planned(FIGURES[name], Settings(quick=True, out=tmp_path))
        with ResultStore(tmp_path / "results.sqlite") as store:
            for p in runs[:store_rows]:
                store.put(p.config.key(), p.config.spec(), result={"x": 1})
            store.put(runs[-1].config.key(), runs[-1].config.spec(), error="ValueError: no")  # not a finished run
            store.put("other", {"seed": 99}, result={"x": 1})  # a run of another study: not this one's to go on from

    def stopped(*args, **kwargs):  # stopped at once, as the runs begin
        raise KeyboardInterrupt

    monkeypatch.setattr(study_runs, "run_sweep", stopped)
    assert main(["figure", name, "--quick", "--out", str(tmp_path)]) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and says in err[0], err
