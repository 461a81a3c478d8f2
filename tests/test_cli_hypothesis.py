"""Property-based fuzz of the command line: any text for any option, any bytes for any file neurowalk reads.

Each example calls :func:`neurowalk.cli.main` in-process (as ``tests/test_cli_fuzz.py`` does, with its tripwires on
the entry points of real work) and checks that it ends in exit 0 or 2, or reaches real work (the tripwire), with at
most one line on stderr and never a traceback. An option's value is text of any kind: empty, blank, numbers of every
size, names from the registries and lists of them, and what a shell passes for bytes that are not UTF-8 (lone
surrogates). Values with "/" stay out (a path could point at any file of the machine); the working folder is a
temporary one.

``NEUROWALK_HYPOTHESIS_EXAMPLES`` (default 100) sets the examples per test, e.g. 2000 for a long search.
"""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import sqlite3
import zipfile

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from neurowalk.cli import build_parser, main
from neurowalk.cli.common import REGISTRIES, registry_names
from test_cli_fuzz import WorkStartedError, _snapshot, fig2_folder, places, tripwires  # noqa: F401 (fixtures)

EXAMPLES = int(os.environ.get("NEUROWALK_HYPOTHESIS_EXAMPLES", "100"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                HealthCheck.too_slow])  # fmt: skip

# --- values --------------------------------------------------------------------------------------------------------

NAMES = sorted({n for r in REGISTRIES for n in registry_names(r)} | {"fig2", "table2", "list", "fixed"})
SPECIAL = ["", " ", "\t", "-", "--", "-1", "0", "1", "nan", "inf", "-inf", "1e400", "0x10", "1_000", "True", "None",
           "size=1", "size=", "=1", "distance=0.3,nan", "scale=0.5", "turn=2", "a=b=c", ",", "open,", ",open", "1,1",
           "-1,-1", "1,2,3", str(2**63), str(10**30), "9" * 400, ".", "..", "~", "$HOME", "*", "\\", "'", '"',
           "\n", "x\ny", "\x1b[31m", "é", "日本", "\u202e", "\ufeff", "\udcff", "mjcf:", "mjcf:none.xml", "--help",
           "-h"]  # fmt: skip

#: Text as a shell passes it: any characters (no NUL, no "/"), bytes that are not UTF-8 as lone surrogates.
TEXT = st.one_of(
    st.sampled_from(SPECIAL),
    st.sampled_from(NAMES),
    st.lists(st.sampled_from(NAMES), min_size=1, max_size=3).map(",".join),
    st.integers().map(str),
    st.floats().map(repr),
    st.text(st.characters(exclude_characters="\x00/", exclude_categories=["Cs"]), max_size=24),
    st.binary(max_size=16).filter(lambda b: b"\x00" not in b and b"/" not in b).map(os.fsdecode),
)


def _options(command: str) -> list[str]:
    """The long options of ``command`` (all but --help), from its parser."""
    (sub,) = [a for a in build_parser()._actions if a.dest == "command"]
    return sorted(o for a in sub.choices[command]._actions for o in a.option_strings if o.startswith("--")
                  and o != "--help")  # fmt: skip


def _pair(option: str, value: str, glued: bool) -> list[str]:
    """``option`` with ``value``: two arguments, or one ``--option=value`` (a value that starts with "-")."""
    return [f"{option}={value}"] if glued else [option, value]


def _call(argv: list[str]) -> tuple[int | None, str]:
    """(exit status, or None where real work was reached; stderr) of ``neurowalk ARGV``."""
    err = io.StringIO()  # takes any str, as the real stderr does (errors="backslashreplace")
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main(argv)
        except WorkStartedError:
            status = None
        except SystemExit as e:  # --help
            status = e.code
    return status, err.getvalue()


def _check(argv: list[str], status: int | None, err: str) -> None:
    assert status in (None, 0, 2), (argv, status, err)
    assert "Traceback" not in err, (argv, err)
    assert len(err.splitlines()) <= 1, (argv, err)
    if status == 2:
        assert err.startswith("neurowalk: error: ") or err.startswith("usage:"), (argv, err)


# --- any text for any option ---------------------------------------------------------------------------------------

#: Each command with arguments that make it tiny (a few steps, the surrogate) and an output folder of its own.
BASE = {
    "run": ["run", "--body", "surrogate", "--steps", "10", "--out", "run-out", "--quiet"],
    "figure": ["figure", "FIGURE", "--quick", "--out", "figure-out"],
    "sweep": ["sweep", "--body", "surrogate", "--steps", "10", "--out", "sweep-out", "--quiet"],
}


#: Figures the option fuzz runs against (between them they take every figure option).
FIGURES = ["fig2", "fig3", "fig5", "fig8", "escape-map", "table2"]


def _option_values(command: str) -> st.SearchStrategy[list[tuple[str, str, bool]]]:
    return st.lists(st.tuples(st.sampled_from(_options(command)), TEXT, st.booleans()), min_size=1, max_size=3)


@pytest.mark.usefixtures("tripwires")
@pytest.mark.parametrize("command", sorted(BASE))
def test_any_text_for_any_option_exits_0_or_2_with_at_most_one_line(command, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)

    @FUZZ
    @given(pairs=_option_values(command), figure=st.sampled_from(FIGURES))
    def check(pairs: list[tuple[str, str, bool]], figure: str) -> None:
        assume(all(v not in (".", "..") for _, v, _ in pairs))  # the working folder's parent is no place to write
        argv = [figure if a == "FIGURE" else a for a in BASE[command]]
        for option, value, glued in pairs:
            argv += _pair(option, value, glued)
        _check(argv, *_call(argv))

    check()


@pytest.mark.usefixtures("tripwires")
def test_any_text_as_the_figure_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)

    @FUZZ
    @given(name=TEXT)
    def check(name: str) -> None:
        argv = ["figure", name, "--quick", "--out", "figure-out"]
        _check(argv, *_call(argv))

    check()


# --- any bytes for any file neurowalk reads ------------------------------------------------------------------------

SPECIAL_BYTES = [b"", b"{}", b"[]", b"null", b"{" * 5000, b'{"params": {}}', b'{"body": "surrogate"}\n' * 3,
                 b"\xef\xbb\xbf{}", b"\x93NUMPY\x01\x00"]  # fmt: skip
BYTES = st.one_of(st.binary(max_size=400), st.text(max_size=200).map(str.encode), st.sampled_from(SPECIAL_BYTES))


def _zip_of(members: list[tuple[str, bytes]]) -> bytes:
    """A zip archive (the container of an npz) holding ``members``."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for name, data in members:
            z.writestr(name, data)
    return buf.getvalue()


#: npz files: any bytes, or a real zip of members with any bytes (so that the arrays' headers are read).
NPZ_BYTES = st.one_of(
    BYTES,
    st.lists(
        st.tuples(st.sampled_from(["n0_branch_i.npy", "x.npy", "x", "../x.npy"]), BYTES),
        max_size=3,
        unique_by=lambda m: m[0],
    ).map(_zip_of),
    BYTES.map(lambda b: _zip_of([("n0_branch_i.npy", b"\x93NUMPY\x01\x00v\x00{'descr': '<f8', " + b)])),
)


@pytest.mark.parametrize("which", ["fig2.json", "fig2.npz"])
def test_any_bytes_as_figure_data_for_replot_exit_0_or_2_and_stay(which, request, tmp_path):
    d = tmp_path / "copy"
    shutil.copytree(request.getfixturevalue("fig2_folder"), d)
    (d / "fig2.png").unlink()

    @FUZZ
    @given(data=BYTES if which.endswith(".json") else NPZ_BYTES)
    def check(data: bytes) -> None:
        (d / which).write_bytes(data)
        before = _snapshot(d)
        argv = ["figure", "fig2", "--replot", "--out", str(d)]
        status, err = _call(argv)
        _check(argv, status, err)
        if status == 2:
            assert _snapshot(d) == before and which in err and "without --replot" in err, err

    check()


#: The input files a command reads, each with the command that reads it (FILE: its path).
READERS = {
    "sweep --specs": ["sweep", "--specs", "FILE", "--out", "sweep-out", "--quiet"],
    "run --params": ["run", "--body", "surrogate", "--steps", "10", "--params", "FILE", "--out", "run-out", "--quiet"],
    "sweep --params": ["sweep", "--body", "surrogate", "--steps", "10", "--params", "FILE", "--out", "sweep-out"],
    "figure --params": ["figure", "table2", "--quick", "--params", "FILE", "--out", "figure-out"],
    "run --body mjcf:": ["run", "--body", "mjcf:FILE", "--steps", "10", "--out", "run-out", "--quiet"],
}


@pytest.mark.usefixtures("tripwires")
@pytest.mark.parametrize("reader", sorted(READERS))
def test_any_bytes_as_an_input_file_exit_0_or_2_and_stay(reader, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "input-file"

    @FUZZ
    @given(data=BYTES)
    def check(data: bytes) -> None:
        path.write_bytes(data)
        argv = [a.replace("FILE", str(path)) for a in READERS[reader]]
        status, err = _call(argv)
        _check(argv, status, err)
        assert path.read_bytes() == data

    check()


def test_any_bytes_as_a_sweeps_result_store_exit_0_or_2_and_stay(tmp_path, monkeypatch):
    import neurowalk.runners.sweep

    def tripped(*args: object, **kwargs: object) -> None:
        raise WorkStartedError("run_sweep")

    monkeypatch.setattr(neurowalk.runners.sweep, "run_sweep", tripped)  # the store itself is opened for real
    out = tmp_path / "sweep-out"
    out.mkdir()
    store = out / "results.sqlite"
    good = tmp_path / "good.sqlite"
    with sqlite3.connect(good) as db:  # an SQLite file of another program: a start for damaged ones
        db.execute("CREATE TABLE t (x)")
    sqlite_head = good.read_bytes()[:100]

    @FUZZ
    @given(data=st.one_of(BYTES.filter(bool), BYTES.map(lambda b: sqlite_head + b)))
    def check(data: bytes) -> None:
        for p in out.iterdir():
            p.unlink()
        store.write_bytes(data)
        argv = ["sweep", "--body", "surrogate", "--steps", "10", "--out", str(out), "--quiet"]
        status, err = _call(argv)
        _check(argv, status, err)
        if status == 2:
            assert store.read_bytes() == data, err

    check()
