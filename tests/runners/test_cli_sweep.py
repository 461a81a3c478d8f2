"""`neurowalk sweep` as a user runs it: grid and specs file, kill -9 and resume, failures, bad input, export."""

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time

import pyarrow.parquet as pq
import pytest

from neurowalk.cli import main
from neurowalk.runners.specs import FIELDS, grid, spec_key


def _rows(db):
    """(key, finished_at) of every stored run, read without writing."""
    if not db.exists():
        return {}
    con = sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=10)
    try:
        return dict(con.execute("SELECT key, finished_at FROM runs"))
    except sqlite3.OperationalError:  # the table is not there yet
        return {}
    finally:
        con.close()


def test_grid_sweep_writes_store_settings_and_parquet(tmp_path, capsys):
    out = tmp_path / "s"
    argv = ["sweep", "--arena", "box", "--controller", "plastic,static", "--seeds", "2", "--seed-start", "5",
            "--steps", "30", "--arena-opt", "distance=0.5,0.8", "--out", str(out), "--quiet"]  # fmt: skip
    assert main([*argv, "--export", "parquet"]) == 0
    info = json.loads((out / "sweep.json").read_text())
    assert info["finished"] and info["counts"]["ok"] == 8 and info["counts"]["skipped"] == 0 and info["failures"] == []
    assert info["settings"]["backend"] == "local" and info["settings"]["arena_opt"] == ["distance=0.5,0.8"]
    tab = pq.read_table(out / "results.parquet")
    assert tab.num_rows == 8 and set(FIELDS) | {"key", "status", "wall_time_s", "coverage"} <= set(tab.column_names)
    assert sorted(tab.column("seed").to_pylist()) == [5, 5, 5, 5, 6, 6, 6, 6]
    assert {json.loads(o)["distance"] for o in tab.column("arena_opts").to_pylist()} == {0.5, 0.8}
    assert "8 runs: 0 already done, 8 ok" in capsys.readouterr().out
    # the same command again: nothing to do; csv export too
    assert main([*argv, "--export", "csv"]) == 0
    info = json.loads((out / "sweep.json").read_text())
    assert info["counts"]["skipped"] == 8 and info["counts"]["ok"] == 0
    assert len((out / "results.csv").read_text().splitlines()) == 9
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # no temp files left


def test_a_body_option_is_a_grid_axis(tmp_path):
    out = tmp_path / "b"
    argv = ["sweep", "--arena", "box", "--body", "surrogate", "--steps", "200", "--body-opt", "turn=0.5,2",
            "--out", str(out), "--quiet", "--workers", "1"]  # fmt: skip
    assert main(argv) == 0
    con = sqlite3.connect(f"file:{out / 'results.sqlite'}?mode=ro", uri=True)
    opts = [json.loads(s)["body_opts"] for (s,) in con.execute("SELECT spec FROM runs")]
    con.close()
    assert sorted(o["turn"] for o in opts) == [0.5, 2.0]
    assert main(["sweep", "--body", "surrogate", "--body-opt", "turn=9", "--out", str(tmp_path / "c"), "--quiet"]) == 2


def test_specs_file(tmp_path):
    specs = tmp_path / "specs.jsonl"
    lines = [{"arena": "open", "steps": 30, "seed": 1}, {"seed": 1, "steps": 30}, {"controller": "static", "steps": 30}]
    specs.write_text("\n".join(json.dumps(s) for s in lines) + "\n")
    assert main(["sweep", "--specs", str(specs), "--workers", "1", "--out", str(tmp_path / "o"), "--quiet"]) == 0
    info = json.loads((tmp_path / "o" / "sweep.json").read_text())
    assert info["counts"] | {"wall_time_s": 0} == {"total": 3, "unique": 2, "duplicates": 1, "skipped": 0, "ok": 2,
                                                   "error": 0, "wall_time_s": 0, "interrupted": False}  # fmt: skip
    assert set(_rows(tmp_path / "o" / "results.sqlite")) == {spec_key(lines[0]), spec_key(lines[2])}


def test_kill_9_then_resume_recomputes_nothing_finished(tmp_path):
    out = tmp_path / "s"
    n = 20
    cmd = [sys.executable, "-m", "neurowalk.cli", "sweep", "--seeds", str(n), "--steps", "300", "--workers", "2",
           "--out", str(out), "--quiet"]  # fmt: skip
    proc = subprocess.Popen(cmd, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while len(_rows(out / "results.sqlite")) < 3 and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.02)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # the driver and its workers, mid-sweep
        proc.wait()
    before = _rows(out / "results.sqlite")
    assert 3 <= len(before) < n, "the sweep was not killed mid-way"
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    after = _rows(out / "results.sqlite")
    keys = {spec_key(s) for s in grid({"steps": 300}, seed=list(range(n)))}
    assert set(after) == keys and len(after) == n  # every run exactly once
    assert all(after[k] == t for k, t in before.items())  # the finished runs were not rerun
    info = json.loads((out / "sweep.json").read_text())
    assert info["counts"]["skipped"] == len(before) and info["counts"]["ok"] == n - len(before)


def test_failed_runs_exit_1_with_one_line_each(tmp_path, capsys, monkeypatch):
    import functools

    import sweep_fns

    from neurowalk.runners import sweep

    monkeypatch.setattr(sweep, "run_sweep", functools.partial(sweep.run_sweep, fn=sweep_fns.fail_on_seed_3))
    assert main(["sweep", "--seeds", "5", "--steps", "30", "--out", str(tmp_path), "--quiet"]) == 1
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert len(err) == 1 and "seed=3" in err[0] and "ValueError: seed 3 is cursed" in err[0]
    assert err[0].startswith("neurowalk: run failed: " + spec_key({"seed": 3, "steps": 30})[:12])
    info = json.loads((tmp_path / "sweep.json").read_text())
    assert info["counts"]["ok"] == 4 and info["counts"]["error"] == 1 and info["failures"][0]["spec"]["seed"] == 3
    last = cap.out.strip().splitlines()[-1]
    assert "1 failed" in last and last.endswith("; run the same command again to run the 1 failed again")
    monkeypatch.undo()  # the same command again: the failed run runs again (and now passes), the others are kept
    assert main(["sweep", "--seeds", "5", "--steps", "30", "--out", str(tmp_path), "--quiet"]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert "4 already done, 1 ok, 0 failed" in last and "run the same command again" not in last


def test_a_sweep_retries_a_job_whose_worker_died_by_default():
    from neurowalk.cli import parse

    assert parse(["sweep"]).retries == 3 and parse(["sweep", "--retries", "0"]).retries == 0


def test_rays_own_log_stays_out_of_the_terminal_unless_asked_for(monkeypatch):
    import logging
    import types

    from neurowalk.runners import ray_backend

    calls = []
    fake = types.SimpleNamespace(is_initialized=lambda: False, init=lambda **kw: calls.append(kw))
    monkeypatch.setattr(ray_backend, "import_ray", lambda: fake)
    monkeypatch.delenv(ray_backend.LOG_ENV, raising=False)
    ray_backend.start(workers=2)
    ray_backend.start(address="10.0.0.1:6379")
    assert all(c["log_to_driver"] is False and c["logging_level"] == logging.ERROR for c in calls)
    monkeypatch.setenv(ray_backend.LOG_ENV, "1")
    ray_backend.start(address="10.0.0.1:6379")
    assert calls[-1]["log_to_driver"] is True and calls[-1]["logging_level"] == logging.INFO


@pytest.mark.parametrize(
    "args,word",
    [
        (["--arena", "open,maze"], "maze"),
        (["--controller", "plastic,wheeled"], "wheeled"),
        (["--body", "wheels"], "wheels"),
        (["--steps", "ten"], "ten"),
        (["--steps", "0"], "steps"),
        (["--seeds", "0"], "--seeds"),
        (["--seed-start", "-1"], "--seed-start"),
        (["--workers", "0"], "--workers"),
        (["--backend", "dask"], "dask"),
        (["--address", "auto"], "--backend ray"),
        (["--arena", "box", "--arena-opt", "distance=0.5,far"], "far"),
        (["--arena", "box", "--arena-opt", "gap=1"], "gap"),
        (["--arena-opt", "novalue"], "KEY=VALUE"),
        (["--export", "xls"], "xls"),
        (["--specs", "missing.jsonl"], "missing.jsonl"),
    ],
)
def test_bad_input_exits_2_with_one_line_before_any_work(args, word, tmp_path, capsys):
    assert main(["sweep", *args, "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and word in err[0]
    assert not (tmp_path / "x").exists()


def test_specs_file_errors_exit_2(tmp_path, capsys):
    specs = tmp_path / "specs.jsonl"
    specs.write_text('{"seed": 1}\n{"seed": 2, "colour": "red"}\n')
    assert main(["sweep", "--specs", str(specs), "--out", str(tmp_path / "x")]) == 2
    assert "colour" in capsys.readouterr().err
    assert main(["sweep", "--specs", str(specs), "--seeds", "3", "--out", str(tmp_path / "x")]) == 2
    assert "--seeds" in capsys.readouterr().err
    specs.write_text("{oops\n")
    assert main(["sweep", "--specs", str(specs), "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "specs.jsonl:1" in err[0]


@pytest.mark.parametrize("content", [b"\x13\x37 not a database " * 500, b"SQLite format 3\x00" + b"\xff" * 4000])
def test_corrupt_store_exits_2_with_one_line(tmp_path, capsys, content):
    (tmp_path / "results.sqlite").write_bytes(content)
    assert main(["sweep", "--steps", "30", "--out", str(tmp_path), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "results.sqlite" in err[0]
    assert (tmp_path / "results.sqlite").read_bytes() == content  # left as it was


def test_ray_backend_without_ray_exits_2_with_the_install_hint(tmp_path, capsys, monkeypatch):
    from neurowalk.runners import ray_backend

    monkeypatch.setitem(sys.modules, "ray", None)  # `import ray` fails as if it were not installed
    with pytest.raises(ray_backend.RayMissingError, match=r"pip install -e '\.\[ray\]'"):
        ray_backend.import_ray()
    assert issubclass(ray_backend.RayMissingError, ImportError)
    assert main(["sweep", "--backend", "ray", "--steps", "30", "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["neurowalk: error: the ray backend needs `pip install -e '.[ray]'` in neurowalk's folder"]
    assert not (tmp_path / "x").exists()


def test_a_broken_ray_install_is_not_hidden(monkeypatch):
    import builtins

    from neurowalk.runners import ray_backend

    real_import = builtins.__import__

    def fake_import(name, *args, **kwargs):
        if name == "ray":
            raise ModuleNotFoundError("No module named 'grpc'", name="grpc")  # ray is there, a dependency is not
        return real_import(name, *args, **kwargs)

    monkeypatch.delitem(sys.modules, "ray", raising=False)
    monkeypatch.setattr(builtins, "__import__", fake_import)
    with pytest.raises(ModuleNotFoundError, match="grpc") as e:
        ray_backend.import_ray()
    assert not isinstance(e.value, ray_backend.RayMissingError)


def test_out_that_is_a_file_exits_2(tmp_path, capsys):
    (tmp_path / "f").write_text("x")
    assert main(["sweep", "--steps", "30", "--out", str(tmp_path / "f"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "f" in err[0]
