"""neurowalk reproduce end to end on two quick results: records, report, resume, bad input, and the plan's shape."""

from __future__ import annotations

import json
import shlex
from pathlib import Path

from neurowalk.cli import main
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.reproduce.plan import ITEMS, PLAN
from neurowalk.experiments.reproduce.runner import rejudged, runs_of
from neurowalk.experiments.reproduce.timing import measured_times


def test_plan_names_real_figures_and_unique_results():
    assert len(ITEMS) == len(PLAN)
    assert all(item.figure in FIGURES for item in PLAN)
    names = {i.name for i in PLAN}
    for must in ("table1", "table2", "table2-physics", "fig8-27hz", "fig9-27hz", "fig10-27hz"):
        assert must in names
    assert {f"fig{k}" for k in range(2, 11)} <= names  # every figure of the paper


def test_results_with_the_same_command_share_one_run():
    runs, of = runs_of([ITEMS["table2"], ITEMS["table2"]], quick=True, workers=None)
    assert len(runs) == 1 and of["table2"] is runs[0]
    runs, of = runs_of([ITEMS["table2"], ITEMS["table2-1000"]], quick=False, workers=None)
    assert len(runs) == 2 and dict(of["table2-1000"].given) == {"seeds": 1000}
    runs, of = runs_of([ITEMS["table2-1000"]], quick=True, workers=None)
    assert dict(of["table2-1000"].given) == {"quick": True, "seeds": 100}
    runs, _ = runs_of([ITEMS["fig8"], ITEMS["fig2"]], quick=True, workers=3)
    assert dict(runs[0].given)["workers"] == 3 and "workers" not in dict(runs[1].given)  # fig2 takes none
    typed = Settings(quick=True, workers=3, out=Path("d/fig8"), shared_runs=Path("d/runs"))
    assert runs[0].settings(Path("d")) == typed


def test_quick_reproduction_of_two_results_records_judges_and_resumes(tmp_path, capsys):
    out = tmp_path / "rep"
    assert main(["reproduce", "--quick", "--only", "fig2,fig4", "--out", str(out)]) == 0
    line = capsys.readouterr().out
    assert "reproduce: 2 results" in line and str(out / "report.md") in line
    for name in ("fig2", "fig4"):
        rec = json.loads((out / f"{name}.json").read_text())
        assert rec["quick"] is True and rec["claims"]
        assert rejudged(ITEMS[name], rec, out) == rec  # the judge's claims of the numbers the figure wrote
        verdicts = {c["verdict"] for c in rec["claims"]}  # all the same: that one; mixed: partly
        assert rec["verdict"] == (verdicts.pop() if len(verdicts) == 1 else "partly")
        assert shlex.split(rec["command"]) == ["neurowalk", "figure", name, "--settings", f"{out}/{name}/settings.json"]
        assert rec["settings"] == {"quick": True} and rec["figure"] == name
        written = json.loads((out / name / "settings.json").read_text())  # what the command read
        assert written == {
            "figure": name,
            "settings": {"quick": True, "out": f"{out}/{name}", "shared_runs": f"{out}/runs"},
        }
        assert rec["versions"]["mujoco"] and rec["wall_time_s"] > 0
        assert (out / rec["files"]["png"]).is_file() and (out / rec["files"]["json"]).is_file()
        assert all(c["rule"] for c in rec["claims"])
    report = (out / "report.md").read_text()
    assert "| [fig2](#fig2) |" in report and "| table2 |" in report and "not run" in report
    details = (out / "details.md").read_text()  # every claim's rule, on the report's second page
    for name in ("fig2", "fig4"):
        rec = json.loads((out / f"{name}.json").read_text())
        assert f"(details.md#{name})" in report and f"## {name}" in details
        assert all(c["rule"] in details for c in rec["claims"])
    stamp = (out / "fig2" / "fig2.json").stat().st_mtime_ns
    assert main(["reproduce", "--quick", "--only", "fig2", "--out", str(out)]) == 0  # resumes: nothing rerun
    assert (out / "fig2" / "fig2.json").stat().st_mtime_ns == stamp
    assert measured_times(tmp_path, out)["figures"]["fig2"]["quick_s"] > 0
    (out / "fig4" / "command.json").unlink()  # fig4 stopped part-way: its store holds some runs
    (out / "fig4" / "results.sqlite").write_bytes(b"")
    assert main(["reproduce", "--quick", "--only", "fig4", "--out", str(out)]) == 0
    assert json.loads((out / "fig4" / "command.json").read_text())["resumed"] is True
    assert "fig4" not in measured_times(tmp_path, out)["figures"]  # the time of a part is no figure's time


def test_bad_input_exits_2_naming_the_value(tmp_path, capsys):
    assert main(["reproduce", "--only", "fig2,nonsense", "--out", str(tmp_path)]) == 2
    assert "nonsense" in capsys.readouterr().err
    assert main(["reproduce", "--workers", "0", "--out", str(tmp_path)]) == 2
    assert "--workers" in capsys.readouterr().err


def test_list_names_every_command_and_runs_nothing(tmp_path, capsys):
    assert main(["reproduce", "--list", "--quick", "--out", str(tmp_path / "x")]) == 0
    text = capsys.readouterr().out
    assert all(item.name in text for item in PLAN) and "figure fig8: control_hz 27, quick" in text
    assert not (tmp_path / "x").exists()


def test_a_reproduce_killed_outright_takes_its_figure_with_it(tmp_path):
    """SIGKILL to `reproduce`: the kernel sends its running figure SIGTERM, and the figure stops (no orphan)."""
    import os
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "rep"
    parent = subprocess.Popen(
        [sys.executable, "-m", "neurowalk", "reproduce", "--quick", "--only", "fig3", "--out", str(out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    child = None
    deadline = time.monotonic() + 60
    while child is None and time.monotonic() < deadline:
        found = subprocess.run(["pgrep", "-P", str(parent.pid)], capture_output=True, text=True).stdout.split()
        child = int(found[0]) if found else None
        time.sleep(0.2)
    assert child is not None, "the figure command never started"
    time.sleep(2)  # the figure is under way
    parent.send_signal(signal.SIGKILL)
    parent.wait()
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        try:
            os.kill(child, 0)
        except ProcessLookupError:
            break
        with open(f"/proc/{child}/stat") as f:  # a zombie (exited, not yet reaped by init) has stopped too
            if f.read().split()[2] == "Z":
                break
        time.sleep(0.2)
    else:
        os.kill(child, signal.SIGKILL)
        raise AssertionError("the figure outlived its reproduce")
    assert not (out / "fig3" / "command.json").exists()  # it did not finish: no record claims it did


def test_a_judge_that_fails_on_a_finished_run_says_where_it_failed(tmp_path, monkeypatch, capsys):
    import dataclasses

    from neurowalk.experiments.reproduce import plan

    def judge(summary, quick):
        return summary["no such key"]

    broken = dataclasses.replace(ITEMS["fig2"], claims=judge)
    monkeypatch.setattr(plan, "PLAN", tuple(broken if i.name == "fig2" else i for i in plan.PLAN))
    monkeypatch.setitem(plan.ITEMS, "fig2", broken)
    main(["reproduce", "--quick", "--only", "fig2", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert "fig2: its judge could not read fig2.json (KeyError: 'no such key', at test_runner.py:" in err
    assert "in judge)" in err and not (tmp_path / "fig2.json").exists()
