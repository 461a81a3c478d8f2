"""The first run's compile is said, once, and the progress bars' pace leaves it out (neurowalk.progress).

The commands run in child processes with an empty numba cache of their own (``NUMBA_CACHE_DIR``) and the note
asked for on a stderr that is not a terminal (``NEUROWALK_COMPILE_NOTE=1``).
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from neurowalk import cli, progress

NOTE = "neurowalk: compiling its kernels once"
ROOT = Path(__file__).resolve().parents[1]


def _env(cache: Path, note: str = "1") -> dict[str, str]:
    return {**os.environ, "NUMBA_CACHE_DIR": str(cache), progress.NOTE_ENV: note}


def _neurowalk(args: list[str], cache: Path) -> subprocess.CompletedProcess[str]:
    cmd = [sys.executable, "-m", "neurowalk", *args]
    return subprocess.run(cmd, env=_env(cache), capture_output=True, text=True, timeout=300)


def _notes(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if NOTE in line]


def _compiled(cache: Path) -> list[Path]:
    """The kernels numba saved in ``cache`` (index files)."""
    return sorted(cache.rglob("*.nbi"))


def test_the_note_comes_once_on_a_cold_cache_and_not_on_a_warm_one(tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    cold = _neurowalk(["figure", "fig2", "--quick", "--out", str(tmp_path / "a")], cache)  # a few small kernels
    assert cold.returncode == 0, cold.stderr
    assert cold.stderr.splitlines() == _notes(cold.stderr), cold.stderr  # the note is all of stderr
    (note,) = _notes(cold.stderr)
    assert note.endswith(f"cached in {cache}/{next(cache.iterdir()).name}") and _compiled(cache)
    warm = _neurowalk(["figure", "fig2", "--quick", "--out", str(tmp_path / "b")], cache)
    assert warm.returncode == 0 and warm.stderr == "", warm.stderr


BAD_INPUT = """
import contextlib, io, json, sys
from neurowalk.cli import main
out = []
for argv in json.loads(sys.argv[1]):
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = main(argv)
    out.append([argv, status, err.getvalue()])
print(json.dumps(out))
"""


def test_bad_input_is_one_line_on_a_cold_cache_and_compiles_nothing(tmp_path: Path) -> None:
    out = str(tmp_path / "out")
    params = tmp_path / "params.json"
    params.write_text('{"no_such_field": 1}')
    cases = [
        ["run", "--steps", "-5", "--out", out],
        ["run", "--arena", "nowhere", "--out", out],
        ["run", "--body", "nobody", "--out", out],
        ["run", "--params", str(params), "--out", out],
        ["run", "--params", str(tmp_path / "missing.json"), "--out", out],
        ["figure", "no-such-figure"],
        ["figure", "table2", "--seeds", "0", "--out", out],
        ["figure", "table2", "--climb", "--body", "surrogate", "--out", out],
        ["figure", "table2", "--control-hz", "27", "--out", out],
        ["figure", "fig2", "--replot", "--out", out],
        ["sweep", "--body", "nobody", "--out", out],
        ["sweep", "--steps", "0", "--out", out],
        ["optimize", "--workers", "0", "--out", out],
        ["baseline", "--methods", "nothing", "--out", out],
    ]
    cache = tmp_path / "cache"
    cmd = [sys.executable, "-c", BAD_INPUT, json.dumps(cases)]
    done = subprocess.run(cmd, env=_env(cache), capture_output=True, text=True, timeout=300, check=True)
    for argv, status, err in json.loads(done.stdout):
        assert status == 2 and len(err.splitlines()) == 1 and NOTE not in err, (argv, err)
    assert _compiled(cache) == []  # nothing ran: no kernel was compiled, so no note could come


POOL = """
import sys
from neurowalk.neural.plasticity import activity
from neurowalk.runners.local import run_unordered


def job(x):
    return activity(x, 0.0)  # a kernel: on a cold cache each worker that runs it first compiles it


if __name__ == "__main__":
    done = sorted((d.index, d.value, d.error) for d in run_unordered(job, [0.5, 0.0, -0.5, 1.0], workers=2))
    print([v for _, v, _ in done], [e for _, _, e in done])
"""


def test_workers_that_compile_give_one_note_from_their_driver(tmp_path: Path) -> None:
    script = tmp_path / "pool.py"
    script.write_text(POOL)
    cache = tmp_path / "cache"
    done = subprocess.run([sys.executable, str(script)], env=_env(cache), capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("] [")[0] == "[0.75, 0.5, 0.25, 1.0", done.stdout
    assert len(_notes(done.stderr)) == 1 and done.stderr.splitlines() == _notes(done.stderr), done.stderr
    assert _compiled(cache)


@pytest.fixture
def fresh(monkeypatch: pytest.MonkeyPatch) -> None:
    """This process as if it had not compiled yet, its note not yet said."""
    monkeypatch.setattr(progress, "_said", False)
    monkeypatch.delenv(progress.NOTE_ENV, raising=False)


@pytest.mark.parametrize(("setting", "written"), [("1", 1), ("0", 0), (None, 1)])  # stderr here: not a terminal
def test_the_note_goes_where_the_setting_says_and_once(setting, written, fresh, monkeypatch, capsys) -> None:
    if setting is not None:
        monkeypatch.setenv(progress.NOTE_ENV, setting)
    progress.compiling(Path("/cache"))
    progress.compiling(Path("/cache"))
    err = capsys.readouterr().err.splitlines()
    assert len(err) == written and all(line.startswith(NOTE) and "/cache" in line for line in err)


def test_the_note_is_written_where_stderr_is_a_terminal_too(fresh, monkeypatch) -> None:
    terminal = io.StringIO()
    terminal.isatty = lambda: True  # type: ignore[method-assign]
    monkeypatch.setattr(sys, "stderr", terminal)
    progress.compiling(Path("/cache"))
    assert terminal.getvalue().startswith(NOTE)


def test_a_note_that_cannot_be_written_does_not_stop_the_work(fresh, monkeypatch) -> None:
    class Gone(io.StringIO):
        def write(self, s: str) -> int:
            raise BrokenPipeError(32, "Broken pipe")

    def driver_gone() -> None:
        raise OSError("the pipe to the driver is closed")

    monkeypatch.setenv(progress.NOTE_ENV, "1")
    monkeypatch.setattr(sys, "stderr", Gone())
    progress.compiling(Path("/cache"))  # no error
    monkeypatch.setattr(progress, "_said", False)
    monkeypatch.setattr(progress, "_forward", driver_gone)
    progress.compiling(Path("/cache"))  # a worker whose driver is gone: no error either


@pytest.mark.parametrize("quiet", [True, False])
def test_quiet_silences_the_note(quiet, fresh, monkeypatch, capsys) -> None:
    monkeypatch.setenv(progress.NOTE_ENV, "1")
    monkeypatch.setitem(cli._COMMANDS, "run", lambda args: progress.compiling(Path("/cache")) or 0)
    assert cli.main(["run", "--out", "x", *(["--quiet"] if quiet else [])]) == 0
    assert len(capsys.readouterr().err.splitlines()) == (0 if quiet else 1)


def test_the_bar_counts_its_pace_from_the_first_finished_unit(monkeypatch) -> None:
    clock = SimpleNamespace(t=1000.0)
    monkeypatch.setattr(progress, "time", SimpleNamespace(time=lambda: clock.t))
    bar = progress.Progress(total=40, unit="run", file=io.StringIO(), mininterval=0)
    clock.t += 37  # the first run: the kernels compile
    bar.update(1)
    assert bar.format_dict["rate"] == 0 and "<?" in str(bar)  # time left unknown, not 39 x 37 s
    clock.t += 2
    bar.update(9)
    assert bar.format_dict["rate"] == pytest.approx(4.5)  # 9 runs in the 2 s since the first finished
    assert "<00:06," in str(bar)  # 30 runs left at 4.5 a second
    bar.close()


def test_a_resumed_bar_starts_its_clock_at_its_first_new_unit(monkeypatch) -> None:
    clock = SimpleNamespace(t=0.0)
    monkeypatch.setattr(progress, "time", SimpleNamespace(time=lambda: clock.t))
    bar = progress.Progress(total=1000, initial=400, file=io.StringIO(), mininterval=0)
    bar.update(0)
    clock.t += 10
    bar.update(100)
    clock.t += 1
    bar.update(100)
    assert bar.format_dict["rate"] == pytest.approx(100)
    bar.close()


def test_the_estimate_in_words_covers_the_committed_measurement() -> None:
    measured = json.loads((ROOT / "docs/benchmarks/compile.json").read_text())["commands"]
    low, high = (float(x) for x in progress.COMPILE_TIME.removeprefix("about ").removesuffix(" s").split("-"))
    assert all(low <= c["first_run_extra_s"] <= high for c in measured.values()), measured


def test_the_page_of_the_first_steps_names_the_compile() -> None:
    for page in ("README.md", "docs/index.md"):
        text = (ROOT / page).read_text()
        assert "benchmarks/compile.json#commands/" in text and "compile" in text, page
