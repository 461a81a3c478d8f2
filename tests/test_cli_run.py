"""`neurowalk run`, `export-model`, `arenas`, `view` as a user runs them."""

import json
import re

import mujoco
import numpy as np
import pytest

from neurowalk.cli import main
from neurowalk.sim.config import EpisodeConfig


def test_run_fixed_writes_summary_trajectory_and_picture(tmp_path, capsys):
    assert main(["run", "--arena", "open", "--controller", "fixed", "--steer", "-1,-1", "--steps", "200",
                 "--out", str(tmp_path), "--quiet"]) == 0  # fmt: skip
    s = json.loads((tmp_path / "summary.json").read_text())
    keys = "arena arena_opts controller body steps seed control_hz escaped trapped coverage path_length_m final_pose"
    for key in (*keys.split(), "final_weights", "wall_time_s", "neurowalk_version"):
        assert key in s
    assert s["steps"] == 200 and s["steer"] == [-1, -1] and s["forward_displacement_m"] > 0
    with np.load(tmp_path / "trajectory.npz") as z:
        assert z["targets"].shape == (200, 19) and z["pose"].shape == (200, 3)
    assert (tmp_path / "run.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    "args,word",
    [
        (["--arena", "maze"], "maze"),
        (["--controller", "wheeled"], "wheeled"),
        (["--controller", "fixed", "--steer", "1"], "--steer"),
        (["--controller", "fixed", "--steer", "2,0"], "--steer"),
        (["--steps", "0"], "steps"),
        (["--steps", "-5"], "steps"),
        (["--arena", "box", "--arena-opt", "gap=1"], "gap"),
        (["--arena-opt", "novalue"], "KEY=VALUE"),
        (["--body", "wheels"], "wheels"),
    ],
)
def test_bad_input_exits_2_with_one_line(args, word, tmp_path, capsys):
    assert main(["run", *args, "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and word in err[0]
    assert not (tmp_path / "x").exists()


def test_export_model_loads_in_plain_mujoco(tmp_path):
    path = tmp_path / "amosii.xml"
    assert main(["export-model", "--out", str(path), "--arena", "box"]) == 0
    m = mujoco.MjModel.from_xml_path(str(path))
    assert m.nu == 19
    assert int(np.sum(m.sensor_type == mujoco.mjtSensor.mjSENS_RANGEFINDER)) == 2


def test_arenas_lists_options(capsys):
    assert main(["arenas"]) == 0
    out = capsys.readouterr().out
    assert "open" in out and "distance=1.0" in out


def test_native_view_without_display_says_so(monkeypatch, capsys):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert main(["view", "--native", "--steps", "10"]) == 1
    assert "no display" in capsys.readouterr().err


@pytest.mark.parametrize("opt", ["gap=0", "gap=-1", "width=0.1", "funnel=80"])
def test_unbuildable_arena_exits_2(opt, tmp_path, capsys):
    assert main(["run", "--arena", "narrow-passage", "--arena-opt", opt, "--out", str(tmp_path / "x")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_figure_seeds_only_where_it_applies(capsys):
    assert main(["figure", "fig2", "--seeds", "3"]) == 2
    assert "no --seeds" in capsys.readouterr().err


def test_figure_climb_only_where_it_applies(capsys):
    assert main(["figure", "fig4", "--climb"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no --climb" in err[0]
    assert main(["figure", "table2", "--climb", "--body", "surrogate"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "amosii" in err[0]


@pytest.mark.parametrize("opt", ["height=-0.1", "height=0", "height=1.0", "height=nan"])
def test_step_height_the_arena_cannot_build_exits_2(opt, tmp_path, capsys):
    assert main(["run", "--arena", "steps", "--arena-opt", opt, "--climb", "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "height" in err[0]
    assert not (tmp_path / "x").exists()


def test_climbing_needs_the_physics_body(tmp_path, capsys):
    assert main(["run", "--body", "surrogate", "--climb", "--out", str(tmp_path / "x")]) == 2
    assert "amosii" in capsys.readouterr().err


@pytest.mark.parametrize(
    "cmd,word",
    [
        (["run", "--steps", "5", "--out", "FILE"], "is a file, not a folder"),
        (["run", "--steps", "5", "--out", "FILE/sub"], "cannot make the folder"),
        (["figure", "fig2", "--quick", "--out", "FILE"], "is a file, not a folder"),
        (["sweep", "--steps", "5", "--out", "FILE"], "is a file, not a folder"),
        (["bench", "--quick", "--out", "FILE"], "is a file, not a folder"),
        (["export-model", "--out", "DIR"], "is a folder; give a file name"),
        (["export-model", "--out", "FILE/model.xml"], "is a file, not a folder"),
    ],
)
def test_an_output_path_that_cannot_be_written_exits_2_before_any_work(cmd, word, tmp_path, capsys):
    f = tmp_path / "a-file"
    f.write_text("keep me")
    args = [a.replace("FILE", str(f)).replace("DIR", str(tmp_path)) for a in cmd]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and word in err[0]
    assert f.read_text() == "keep me"


def test_ctrl_c_in_a_figure_says_what_it_kept(monkeypatch, tmp_path, capsys):
    import dataclasses

    from neurowalk.experiments import FIGURES

    def stop(settings, runs):
        raise KeyboardInterrupt

    monkeypatch.setitem(FIGURES, "fig2", dataclasses.replace(FIGURES["fig2"], measure=stop))
    assert main(["figure", "fig2", "--out", str(tmp_path)]) == 130
    err = capsys.readouterr().err
    said = "neurowalk: fig2 interrupted; it runs no episode (the network alone), so none is kept: run it again"
    assert err.strip() == said


def test_a_folder_with_an_unfinished_run_is_refused_unless_overwritten(tmp_path, capsys):
    parts = tmp_path / "trajectory.parts"
    parts.mkdir()
    (parts / "part-0000000000.npz").write_bytes(b"a killed run's rows")
    args = ["run", "--body", "surrogate", "--steps", "50", "--out", str(tmp_path), "--quiet"]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unfinished run" in err[0] and "--overwrite" in err[0]
    assert (parts / "part-0000000000.npz").exists()  # kept
    assert main([*args, "--overwrite"]) == 0
    assert not parts.exists() and (tmp_path / "summary.json").exists()


def test_a_reused_folder_holds_only_the_new_runs_files(tmp_path):
    (tmp_path / "video.mp4").write_bytes(b"an earlier run's video")
    assert main(["run", "--body", "surrogate", "--steps", "50", "--out", str(tmp_path), "--quiet"]) == 0
    files = sorted(p.name for p in tmp_path.iterdir())  # no lock file: the lock is on the folder itself
    assert files == ["run.png", "summary.json", "trajectory.npz"]


def test_signals_are_held_during_the_final_save():
    import os
    import signal

    from neurowalk.cli.run import signals_held

    seen = []
    old = signal.signal(signal.SIGTERM, lambda *a: seen.append("term"))
    try:
        with signals_held():
            os.kill(os.getpid(), signal.SIGTERM)  # ignored: the save would finish
        assert seen == []
        os.kill(os.getpid(), signal.SIGTERM)  # the handler is back afterwards
        assert seen == ["term"]
    finally:
        signal.signal(signal.SIGTERM, old)


def _stop_at_step(monkeypatch, step: int, sig: int) -> None:
    """Parts (and checkpoints) every 100 steps; ``sig`` sent to this process as the run's step ``step`` starts."""
    import functools
    import os

    from neurowalk.body.amosii import AmosII
    from neurowalk.sim import episode

    monkeypatch.setattr(episode, "Streaming", functools.partial(episode.Streaming, chunk=100))
    real, calls = AmosII.advance, []

    def advance(self: AmosII) -> None:
        calls.append(1)
        if len(calls) == step:
            os.kill(os.getpid(), sig)
        real(self)

    monkeypatch.setattr(AmosII, "advance", advance)


def _rows(path):
    with np.load(path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


RUN300 = ["run", "--arena", "box", "--steps", "300", "--quiet"]


def _stopped(monkeypatch, capsys, out, step: int, sig: int, then: str):
    """Run RUN300 into ``out``, stopped by ``sig`` at ``step``; the match of its stop line, whose end is ``then``
    (a regex), after "kept the N completed steps in DIR (summary.json, trajectory.npz, run.png); "."""
    import re

    _stop_at_step(monkeypatch, step, sig)
    assert main([*RUN300, "--out", str(out)]) == 128 + sig
    line = capsys.readouterr().err.strip()
    m = re.fullmatch(
        r"neurowalk: interrupted: kept the (\d+) completed steps in (\S+) \(summary.json, trajectory.npz, run.png\); "
        + then,
        line,
    )
    assert m is not None, line
    return m


def test_a_run_stopped_before_its_first_checkpoint_keeps_its_rows_once(tmp_path, monkeypatch, capsys):
    import signal

    out = tmp_path / "run"
    assert signal.SIGTERM + 128 == 143
    then = r"no checkpoint yet: `--resume` starts it again from step 0 \(its settings kept in (\S+)\)"
    m = _stopped(monkeypatch, capsys, out, 50, signal.SIGTERM, then)
    assert m.group(2) == str(out) and m.group(3) == str(out / "trajectory.parts" / "run.json")
    assert len(_rows(out / "trajectory.npz")["t"]) == int(m.group(1)) > 0
    assert [p.name for p in (out / "trajectory.parts").iterdir()] == ["run.json"]  # no second copy of the rows
    spec = json.loads((out / "trajectory.parts" / "run.json").read_text())
    assert spec.pop("resumable") is True  # the CPU loop keeps checkpoints
    assert spec == EpisodeConfig(arena="box", steps=300).spec()  # the run's spec, as a store keeps it
    monkeypatch.undo()
    assert main([*RUN300, "--out", str(out)]) == 2  # a folder with an unfinished run: --resume or --overwrite
    assert "--resume" in capsys.readouterr().err
    assert main([*RUN300, "--out", str(out), "--resume"]) == 0
    err = capsys.readouterr().err.strip()
    assert err == f"neurowalk: no checkpoint yet in {out / 'trajectory.parts'}: starting the run again at step 0"
    assert json.loads((out / "summary.json").read_text())["completed"] and not (out / "trajectory.parts").exists()


def test_a_run_stopped_after_a_checkpoint_keeps_what_resume_needs_and_resumes_bit_for_bit(tmp_path, monkeypatch,
                                                                                          capsys):  # fmt: skip
    import functools
    import signal

    from neurowalk.sim import episode

    whole = tmp_path / "whole"
    monkeypatch.setattr(episode, "Streaming", functools.partial(episode.Streaming, chunk=100))
    assert main([*RUN300, "--out", str(whole)]) == 0
    out = tmp_path / "run"
    assert signal.SIGINT + 128 == 130
    then = r"`--resume` goes on from step 200 \(its checkpoint and rows kept in (\S+)\)"
    m = _stopped(monkeypatch, capsys, out, 250, signal.SIGINT, then)
    done, parts = int(m.group(1)), out / "trajectory.parts"
    assert 200 < done < 300 and m.group(3) == str(parts)
    assert len(_rows(out / "trajectory.npz")["t"]) == done
    held = sorted(p.name for p in parts.iterdir())
    assert held == ["checkpoint.npz", "part-0000000000.npz", "part-0000000100.npz", "run.json"]  # none after step 200
    monkeypatch.undo()
    monkeypatch.setattr(episode, "Streaming", functools.partial(episode.Streaming, chunk=100))
    assert main([*RUN300, "--out", str(out), "--resume"]) == 0
    assert f"resuming the run in {parts} at step 200 of 300" in capsys.readouterr().err
    a, b = _rows(out / "trajectory.npz"), _rows(whole / "trajectory.npz")
    assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)
    assert not parts.exists()


def test_a_run_stopped_before_its_first_step_says_what_it_wrote(tmp_path, monkeypatch, capsys):
    import signal

    out = tmp_path / "run"
    _stop_at_step(monkeypatch, 1, signal.SIGTERM)
    assert main([*RUN300, "--out", str(out)]) == 143
    line = capsys.readouterr().err.strip()
    assert line.startswith(f"neurowalk: interrupted: kept the 0 completed steps in {out} (summary.json); "), line
    assert sorted(p.name for p in out.iterdir()) == ["summary.json", "trajectory.parts"]


def _out_commands() -> dict[str, list[str]]:
    """Every command that takes --out, with the arguments it needs besides."""
    from neurowalk.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    needs = {"figure": ["fig4"]}
    return {
        name: needs.get(name, [])
        for name, p in sub.choices.items()
        if any("--out" in a.option_strings for a in p._actions)
    }


@pytest.mark.parametrize(
    "value",
    ["a" * 300, "new/" + "a" * 300, "/".join(["b" * 200] * 25)],
    ids=["name-over-NAME_MAX", "in-a-new-folder", "path-over-PATH_MAX"],
)
def test_an_output_path_too_long_exits_2_in_one_line_for_every_command(value, tmp_path, monkeypatch, capsys):
    commands = _out_commands()
    assert {"run", "figure", "sweep", "reproduce", "optimize", "baseline", "export-model", "bench"} <= set(commands)
    monkeypatch.chdir(tmp_path)
    for name, args in commands.items():
        assert main([name, *args, "--out", value]) == 2, name
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "too long" in err[0] and "--out" in err[0], (name, err)
        assert len(err[0]) < 200 and "characters, shortened" in err[0], err[0]  # the value named, not echoed whole
    assert list(tmp_path.iterdir()) == []  # nothing made


def test_a_computed_output_path_too_long_is_a_usage_error(tmp_path):
    from neurowalk.cli import UsageError, out_file, out_folder

    with pytest.raises(UsageError, match="too long"):
        out_folder(tmp_path / "new" / ("a" * 300))
    with pytest.raises(UsageError, match="too long"):
        out_file(tmp_path / "new" / ("a" * 300 + ".xml"))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "args,said",
    [
        (["--arena", "steps", "--arena-opt", "height=0.06", "--climb", "--steps", "1700"], "; climbed at 1"),
        (["--arena", "steps", "--arena-opt", "height=0.18", "--climb", "--steps", "300"], "; did not climb; ended"),
        (["--arena", "narrow-passage", "--steps", "50"], "; did not escape; ended"),
        (["--arena", "open", "--steps", "50"], "real time); ended"),
    ],
    ids=["climbed", "wall", "dead end", "no exit"],
)
def test_a_runs_line_says_its_outcome_in_words(args, said, tmp_path, capsys):
    assert main(["run", *args, "--out", str(tmp_path)]) == 0
    line = capsys.readouterr().out.strip().splitlines()[-1]
    assert said in line
    s = json.loads((tmp_path / "summary.json").read_text())
    assert ("climbed at" in line) == (s["exit_step"] is not None)
    assert s.get("climbed") == (None if "--climb" not in args else s["exit_step"] is not None)
    m = re.search(r"ended (\d+\.\d+) m from its start \(([-+]\d+\.\d+) m ahead\), path (\d+\.\d+) m", line)
    assert m is not None, line
    assert [float(v) for v in m.groups()] == [
        round(s[k], 2) for k in ("net_displacement_m", "forward_displacement_m", "path_length_m")
    ]
    if "--climb" in args:
        assert s["physics"]["timestep_s"] == 0.01 and s["body_opts"] == {}  # one physics, climbing or not
