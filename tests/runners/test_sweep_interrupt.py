"""`neurowalk sweep` stopped by SIGINT or SIGTERM at any moment of its life: before its pool starts, while its workers
start, mid-run, while it stores a result, while it writes its summary.

Each try must end within 10 s with exit 130 (SIGINT) or 143 (SIGTERM) and one line on stderr that tells what the store
holds, leave no process of its own behind, and leave a store whose rows are those of an uninterrupted sweep; a rerun
into the same folder finishes the grid with the same rows. The signal goes to the whole process group (as a terminal's
Ctrl-C does) or to the driver alone (as ``kill`` does).

The moments are read from the sweep itself, not from a clock started with it, so that they hit the same phases on a
loaded machine: its readiness (its handlers for SIGINT and SIGTERM in place, ``readiness.py``) and a few ms after,
its first worker, the runs in its store.
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
from collections.abc import Callable
from pathlib import Path

import pytest

from neurowalk.cli import main
from readiness import catches_stop_signals

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")

GRID = ["sweep", "--arena", "simple-deadlock", "--controller", "plastic,static", "--body", "surrogate", "--steps",
        "3000", "--quiet"]  # fmt: skip
KEPT = re.compile(r"^neurowalk: (sweep )?interrupted(: (\d+) of its (\d+) runs are done and kept in (\S+); .*| before "
                  r"its first run; nothing was run)?$")  # fmt: skip


def _start(out: Path, seeds: int) -> subprocess.Popen:
    cmd = [sys.executable, "-m", "neurowalk", *GRID, "--seeds", str(seeds), "--out", str(out)]
    return subprocess.Popen(cmd, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _group(pgid: int) -> list[int]:
    """Live (not zombie) processes of the process group ``pgid``."""
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            out.append(int(stat.parent.name))
    return out


def _rows(db: Path) -> dict[str, tuple]:
    """(spec, status, result, error) of every stored run by key (the machine's times left out)."""
    if not db.exists():
        return {}
    con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
    try:
        return {k: rest for k, *rest in con.execute("SELECT key, spec, status, result, error FROM runs")}
    except sqlite3.OperationalError:  # no table yet
        return {}
    finally:
        con.close()


def _count(db: Path) -> int:
    try:
        con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
    except sqlite3.Error:
        return 0
    try:
        return int(con.execute("SELECT count(*) FROM runs").fetchone()[0])
    except sqlite3.Error:
        return 0
    finally:
        con.close()


def ready(extra: float = 0.0) -> Callable[[subprocess.Popen, Path, float], bool]:
    """A moment: ``extra`` s after the sweep's handlers for SIGINT and SIGTERM are in place (its first moment ready for
    them: the interpreter started, its modules not yet loaded)."""
    seen: list[float] = []

    def when(proc: subprocess.Popen, out: Path, t: float) -> bool:
        if not seen and catches_stop_signals(proc.pid):
            seen.append(t)
        return bool(seen) and t >= seen[0] + extra

    return when


def workers_up(extra: float = 0.0) -> Callable[[subprocess.Popen, Path, float], bool]:
    """A moment: ``extra`` s after the first worker process appeared."""
    seen: list[float] = []

    def when(proc: subprocess.Popen, out: Path, t: float) -> bool:
        if not seen and len(_group(proc.pid)) > 1:
            seen.append(t)
        return bool(seen) and t >= seen[0] + extra

    return when


def stored(n: int) -> Callable[[subprocess.Popen, Path, float], bool]:
    """A moment: the store holds ``n`` runs."""
    return lambda proc, out, t: _count(out / "results.sqlite") >= n


def _try(out: Path, seeds: int, when: Callable, sig: int, group: bool) -> str | None:
    """Start a sweep, send ``sig`` at the moment ``when`` says; None if it had ended before. Checks the ending; returns
    its line."""
    proc = _start(out, seeds)
    t_start = time.monotonic()
    while proc.poll() is None and not when(proc, out, time.monotonic() - t_start):
        time.sleep(0.0005)
    if proc.poll() is not None:
        proc.communicate()
        return None
    at = time.monotonic() - t_start
    (os.killpg if group else os.kill)(proc.pid, sig)
    t0 = time.monotonic()
    try:
        _, err = proc.communicate(timeout=10)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        pytest.fail(f"the sweep signalled at {at:.2f} s did not end within 10 s")
    while _group(proc.pid) and time.monotonic() - t0 < 10:
        time.sleep(0.02)
    where = f"signal {sig} at {at:.2f} s ({'group' if group else 'driver'})"
    assert not _group(proc.pid), f"{where}: processes left: {_group(proc.pid)}"
    assert time.monotonic() - t0 < 10, where
    assert proc.returncode == 128 + sig, f"{where}: exit {proc.returncode}: {err}"  # 130 SIGINT, 143 SIGTERM
    lines = err.strip().splitlines()
    assert len(lines) == 1 and KEPT.match(lines[0]), f"{where}: {err}"
    return lines[0]


def _check_kept(out: Path, line: str, reference: dict[str, tuple]) -> None:
    """The store holds what the line says, and each of its rows is the uninterrupted sweep's."""
    rows = _rows(out / "results.sqlite")
    assert all(rows[k] == reference[k] for k in rows), line
    m = KEPT.match(line)
    assert m is not None
    if m.group(3) is None:  # stopped while it started, before the store was opened
        assert not rows, line
        return
    assert int(m.group(3)) == sum(r[1] == "ok" for r in rows.values()) and int(m.group(4)) == len(reference), line
    assert m.group(5) == str(out / "results.sqlite")
    info = json.loads((out / "sweep.json").read_text())
    assert info["finished"] is False or int(m.group(3)) == len(reference), line


def _reference(tmp_path: Path, seeds: int) -> dict[str, tuple]:
    out = tmp_path / "reference"
    assert main([*GRID, "--seeds", str(seeds), "--out", str(out)]) == 0
    rows = _rows(out / "results.sqlite")
    assert len(rows) == 2 * seeds and all(r[1] == "ok" for r in rows.values())
    return rows


@pytest.mark.slow
def test_sigint_at_20_moments_ends_each_try_cleanly_and_the_rerun_finishes_the_grid(tmp_path):
    seeds = 60  # 120 runs
    reference = _reference(tmp_path, seeds)
    moments = [
        ready(),
        ready(0.002),
        ready(0.02),
        ready(0.1),
        ready(0.3),  # imports, store
        workers_up(),
        workers_up(0.005),
        workers_up(0.02),
        workers_up(0.05),  # the pool starts
        *(stored(n) for n in (1, 2, 10, 30, 50, 70, 90, 110, 118, 119)),  # runs arrive and are stored
        stored(120),
    ]  # the summary (it may end before the signal comes)
    tries = []
    for k, when in enumerate(moments):
        out = tmp_path / f"try{k}"
        line = _try(out, seeds, when, signal.SIGINT, group=k % 2 == 0)
        if line is not None:
            _check_kept(out, line, reference)
            tries.append(out)
    assert len(tries) >= 19, "the sweeps ended before their signal"
    for out in (tries[3], tries[7], tries[-2]):  # before, amid and after the pool's start
        assert main([*GRID, "--seeds", str(seeds), "--out", str(out)]) == 0
        assert _rows(out / "results.sqlite") == reference


def test_sigint_and_sigterm_at_a_few_moments(tmp_path):
    seeds = 20  # 40 runs
    reference = _reference(tmp_path, seeds)
    moments = [(ready(), signal.SIGTERM), (ready(0.005), signal.SIGINT), (ready(0.1), signal.SIGTERM),
               (workers_up(), signal.SIGTERM), (stored(10), signal.SIGINT), (stored(30), signal.SIGTERM)]  # fmt: skip
    for k, (when, sig) in enumerate(moments):
        out = tmp_path / f"try{k}"
        line = _try(out, seeds, when, sig, group=k % 2 == 1)
        assert line is not None, f"try {k} ended before its signal"
        _check_kept(out, line, reference)
    out = tmp_path / "try4"
    assert main([*GRID, "--seeds", str(seeds), "--out", str(out)]) == 0
    assert _rows(out / "results.sqlite") == reference
