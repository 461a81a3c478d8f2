"""optimize, baseline and calibrate stopped by their first SIGINT or SIGTERM: exit 130 or 143 within 10 s, one line
saying what is kept, no traceback, no process of theirs left, and what the line says is kept is on disk (a rerun goes
on from it).

Tiny sizes: each command runs for a few seconds.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from neurowalk.cli import main
from neurowalk.runners.store import count_finished

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")

OPTIMIZE = ["optimize", "--quick", "--population", "3", "--generations", "2", "--environments", "2", "--heldout", "2",
            "--steps", "300", "--deadend-seeds", "1", "--quiet"]  # fmt: skip
BASELINE = ["baseline", "--methods", "neuroevo", "--quick", "--generations", "4", "--population", "4", "--envs", "2",
            "--episode-steps", "100", "--eval-envs", "2", "--eval-steps", "200", "--quiet"]  # fmt: skip


def _group(pgid: int) -> list[int]:
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            out.append(int(stat.parent.name))
    return out


def _stop(args: list[str], when: Callable[[subprocess.Popen], bool], sig: int) -> str:
    """Run ``neurowalk ARGS`` in a session of its own, send ``sig`` to it (the whole group, as a terminal does) once
    ``when`` holds; check how it ends; its line."""
    proc = subprocess.Popen([sys.executable, "-m", "neurowalk", *args], start_new_session=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    deadline = time.monotonic() + 300
    while proc.poll() is None and not when(proc) and time.monotonic() < deadline:
        time.sleep(0.01)
    assert proc.poll() is None, f"{args[0]} ended before its signal: {proc.communicate()[1]}"
    os.killpg(proc.pid, sig)
    t0 = time.monotonic()
    try:
        _, err = proc.communicate(timeout=10)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        pytest.fail(f"{args[0]} did not end within 10 s of its signal")
    while _group(proc.pid) and time.monotonic() - t0 < 10:
        time.sleep(0.02)
    assert not _group(proc.pid), f"processes left: {_group(proc.pid)}"
    assert proc.returncode == 128 + sig, err  # 130 for SIGINT, 143 for SIGTERM
    assert "Traceback" not in err and "Error" not in err, err
    lines = [line for line in err.splitlines() if line.strip() and "%|" not in line]  # calibrate's progress bars aside
    assert len(lines) == 1 and lines[0].startswith(f"neurowalk: {args[0]} interrupted"), err
    return lines[0]


def test_optimize_stops_on_sigint_and_sigterm_and_keeps_what_it_says(tmp_path):
    out = tmp_path / "opt"
    args = [*OPTIMIZE, "--out", str(out)]
    line = _stop(args, lambda p: count_finished(out / "results.sqlite") >= 10, signal.SIGINT)  # amid generation 1
    m = re.match(r"neurowalk: optimize interrupted: (\d+) finished runs are kept in (\S+)(, and the search state after "
                 r"its last finished generation in (\S+))?; run the same command again to resume$", line)  # fmt: skip
    assert m is not None, line
    assert int(m.group(1)) == count_finished(out / "results.sqlite") >= 10 and m.group(2) == str(out / "results.sqlite")
    assert (m.group(4) is not None) == (out / "cmaes.json").is_file()
    line = _stop(args, lambda p: (out / "cmaes.json").is_file(), signal.SIGTERM)  # after a generation
    assert f", and the search state after its last finished generation in {out / 'cmaes.json'}" in line
    kept = count_finished(out / "results.sqlite")
    assert main(args) == 0 and (out / "best.json").is_file()
    assert count_finished(out / "results.sqlite") > kept


def test_baseline_stops_on_sigterm_and_names_the_checkpoints_it_kept(tmp_path):
    out = tmp_path / "bl"
    args = [*BASELINE, "--out", str(out)]
    line = _stop(args, lambda p: (out / "training" / "neuroevo" / "state.json").is_file(), signal.SIGTERM)
    m = re.match(rf"neurowalk: baseline interrupted; kept in {re.escape(str(out))}: (.*); run the same command again "
                 r"to go on from them$", line)  # fmt: skip
    assert m is not None, line
    named = m.group(1).split(", ")
    assert "training/neuroevo/state.json" in named and all((out / n).is_file() for n in named if " (" not in n)
    assert main(args) == 0 and (out / "baselines.json").is_file()


def test_calibrate_stopped_while_measuring_keeps_its_drives_and_goes_on_from_them(tmp_path, capsys):
    target = tmp_path / "cal" / "calibration-wheeled.json"
    store = target.parent / "results.sqlite"
    args = ["calibrate", "--body", "wheeled", "--quick", "--out", str(target)]
    line = _stop(args, lambda p: count_finished(store) >= 3, signal.SIGINT)  # amid its steady drives
    assert line == (
        f"neurowalk: calibrate interrupted before its measurement ended; the drives it finished are kept in {store}: "
        "run the same command again to go on from them"
    ), line
    kept = count_finished(store)
    assert kept >= 3 and not target.exists() and not target.with_suffix(".png").exists()
    assert sorted(p.name for p in target.parent.iterdir()) == ["results.sqlite", "results.sqlite.lock"]  # no temp file
    assert main(args) == 0
    assert f"going on from the {kept} finished jobs kept in {target.parent}" in capsys.readouterr().out
    again = json.loads(target.read_text())
    fresh = tmp_path / "fresh" / "calibration-wheeled.json"  # the same calibration, never stopped
    assert main(["calibrate", "--body", "wheeled", "--quick", "--out", str(fresh)]) == 0
    first = json.loads(fresh.read_text())
    for d in (again, first):
        d["meta"].pop("wall_time_s")
    assert again == first  # bit for bit: the kept drives are the drives


def test_calibrate_stopped_before_a_drive_finished_keeps_nothing(tmp_path):
    target = tmp_path / "cal.json"
    started: list[float] = []

    def measuring(proc: subprocess.Popen) -> bool:  # as soon as its workers started
        if not started and len(_group(proc.pid)) > 1:
            started.append(time.monotonic())
        return bool(started)

    line = _stop(["calibrate", "--quick", "--out", str(target)], measuring, signal.SIGINT)
    assert line in (
        "neurowalk: calibrate interrupted before any of its drives finished; nothing is kept",
        f"neurowalk: calibrate interrupted before its measurement ended; the drives it finished are kept in "
        f"{tmp_path / 'results.sqlite'}: run the same command again to go on from them",
    ), line
    assert not target.exists() and not target.with_suffix(".png").exists()
    assert count_finished(tmp_path / "results.sqlite") == 0 or "are kept in" in line
