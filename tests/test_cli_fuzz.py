"""Fuzz of the command line: every bad input to every command exits 2 with one line naming it, before any work.

Each case calls :func:`neurowalk.cli.main` in-process with one bad input and checks that

1. it returns 2 (bad input),
2. stderr is exactly one non-empty line, without a traceback, naming the offending value or flag,
3. a good run folder made once per module is unchanged (listing, bytes, mtimes): the cases that take an output
   point ``--out`` at it, or at a path inside it,
4. no work started: the entry points of the real work (a run, a sweep, a figure, a calibration, a benchmark, a
   search, a model export) are replaced by a tripwire for the duration of a case.

Placeholders in a case's argv: ``<good>`` is the good run folder, ``<files>`` a folder of prepared input files
(bad params files and specs files, written once per module from :data:`FILES`).
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import importlib
import json
import pkgutil
from pathlib import Path
from typing import Any

import pytest

from neurowalk import cli
from neurowalk.cli import main
from neurowalk.experiments import FIGURES

GOOD = "<good>"
FILES_DIR = "<files>"
#: Input files of the cases: name -> content (str, or bytes for a file that is not text).
FILES: dict[str, str | bytes] = {}


def _file(name: str, content: str | bytes) -> str:
    """Register a prepared input file; returns its argv placeholder."""
    assert FILES.get(name, content) == content, name
    FILES[name] = content
    return f"{FILES_DIR}/{name}"


def case(word: str, *argv: str, xfail: str | None = None, xfail_if: bool = True) -> Any:
    """One bad input: ``argv`` (placeholders allowed) and a short ``word`` the error line must contain.

    ``xfail``: the reason of a known bug in a file this test may not fix (strict: the fix makes the case fail);
    ``xfail_if``: where the bug shows (e.g. only as root).
    """
    marks = [pytest.mark.xfail(xfail_if, reason=xfail, strict=True)] if xfail else []
    shown = " ".join(_short(a) for a in argv) or "(no arguments)"
    return pytest.param(list(argv), word, id=shown, marks=marks)


def _short(arg: str) -> str:
    """An argument as a test id shows it: '' for an empty one, a long one cut (its length said)."""
    return "''" if not arg else arg if len(arg) <= 40 else f"{arg[:16]}...({len(arg)} chars)"


# --- run ---------------------------------------------------------------------------------------------------------


def run(word: str, *args: str, xfail: str | None = None) -> Any:
    """A bad `neurowalk run` whose --out is the good folder (unless the case gives its own --out)."""
    out = () if "--out" in args else ("--out", GOOD)
    return case(word, "run", *args, *out, "--quiet", xfail=xfail)


def params_file(name: str, content: str | bytes) -> str:
    return _file(f"params-{name}.json", content)


P_NOT_JSON = params_file("notjson", "{mu_b: 1")
P_EMPTY = params_file("empty", "")
P_LIST = params_file("list", "[1, 2]")
P_NO_PARAMS = params_file("noparams", '{"variant": "paper"}')
P_PARAMS_LIST = params_file("paramslist", '{"params": [0.01]}')
P_UNKNOWN = params_file("unknown", '{"params": {"speed": 1}}')
P_NAN = params_file("nan", '{"params": {"mu_b": NaN}}')
P_INF = params_file("inf", '{"params": {"mu_q": Infinity}}')
P_HUGE = params_file("huge", '{"params": {"gamma_b": 1e400}}')
P_STRING = params_file("string", '{"params": {"k": "fast"}}')
P_BOOL = params_file("bool", '{"params": {"a": true}}')
P_NEGATIVE = params_file("negative", '{"params": {"gamma_q": -0.001}}')
P_CUTOFF = params_file("cutoff", '{"params": {"activity_cutoff": 5}}')
P_TUNED = params_file("tuned", '{"params": {"mu_b": 0.01}, "variant": "tuned"}')
P_BOGUS_VARIANT = params_file("bogusvariant", '{"params": {"mu_b": 0.01}, "variant": "bogus"}')
P_BINARY = params_file("binary", b"\xff\xfe\x00\x81 not text")
P_DEEP = params_file("deep", '{"params": ' + "[" * 100_000)
P_MISSING = f"{FILES_DIR}/no-such-params.json"
P_FOLDER = f"{FILES_DIR}/a-folder"

M_BLIND = _file("blind.xml", '<mujoco><worldbody><body><freejoint/><geom size="0.1"/></body></worldbody></mujoco>')

RUN_CASES = [
    run("control_hz", "--control-hz", "0"),
    run("control_hz", "--control-hz", "-27"),
    run("fast", "--control-hz", "fast"),
    run("calibrated", "--body", "surrogate", "--control-hz", "27"),
    run("maze", "--arena", "maze"),
    run("no such file", "--body", f"mjcf:{FILES_DIR}/none.xml"),
    run("US_L", "--body", f"mjcf:{M_BLIND}"),
    run("'eyes'", "--body", f"mjcf:{M_BLIND}", "--body-opt", "eyes=2"),
    run("cannot load", "--body", f"mjcf:{FILES_DIR}/params-list.json"),
    run("scale", "--body", "wheeled", "--body-opt", "scale=huge"),
    run("scale", "--body", "wheeled", "--body-opt", "scale=0"),
    run("scale", "--body", "wheeled", "--body-opt", "scale=nan"),
    run("size", "--body", "wheeled", "--body-opt", "size=1"),
    run("turn", "--body", "surrogate", "--body-opt", "turn=0.1"),
    run("speed", "--body", "surrogate", "--body-opt", "speed=inf"),
    run("scale", "--body-opt", "scale=0.5"),
    run("--body-opt", "--body", "wheeled", "--body-opt", "scale"),
    run("tripod", "--body", "wheeled", "--gait", "tripod"),
    run("wheeled", "--body", "wheeled", "--climb"),
    run("''", "--arena", ""),
    run("wheeled", "--controller", "wheeled"),
    run("PLASTIC", "--controller", "PLASTIC"),
    run("wheels", "--body", "wheels"),
    run("steps", "--steps", "0"),
    run("steps", "--steps", "-5"),
    run("1e3", "--steps", "1e3"),
    run("lots", "--steps", "lots"),
    run("steps", "--steps", "100000001"),
    run("steps", "--steps", "99999999999999999999999999"),
    run("steps", "--steps", str(10**400)),
    run("--steps", "--steps"),
    run("seed", "--seed", "-1"),
    run("seed", "--seed", str(2**63)),
    run("seed", "--seed", str(-(10**400))),
    run("1.5", "--seed", "1.5"),
    run("--steer", "--controller", "fixed", "--steer", "1"),
    run("--steer", "--controller", "fixed", "--steer", "2,0"),
    run("--steer", "--controller", "fixed", "--steer", "nan,0"),
    run("--steer", "--controller", "fixed", "--steer", "0,-inf"),
    run("--steer", "--controller", "fixed", "--steer", "left,right"),
    run("--steer", "--controller", "fixed", "--steer", "1,1,1"),
    run("--steer", "--controller", "fixed", "--steer", ""),
    run("steer", "--steer", "-1,-1"),
    run("fixed", "--controller", "fixed"),
    run("gallop", "--gait", "gallop"),
    run("tripod", "--body", "surrogate", "--gait", "tripod"),
    run("bogus", "--variant", "bogus"),
    run("--variant", "--variant", ""),
    run("Paper", "--variant", "Paper"),
    run("reflexes", "--body", "surrogate", "--climb"),
    run("reflexes", "--body", "surrogate", "--reflexes"),
    run("backbone", "--body", "surrogate", "--backbone"),
    run("--video", "--body", "surrogate", "--video"),
    run("--resume", "--resume"),
    run("steps", "--overwrite", "--steps", "0"),
    run("--bogus", "--bogus"),
    run("unrecognized arguments: two\\nlines", "two\nlines"),
    run("unrecognized arguments: \\x1b[2J\\udcff", "\x1b[2J\udcff"),  # a terminal's escape; bytes not UTF-8
    run("summary.json", "--out", f"{GOOD}/summary.json"),
    run("summary.json", "--out", f"{GOOD}/summary.json/sub"),
    run("xxxx", "--out", f"{GOOD}/{'x' * 300}"),
    run("neurowalk-run", "--out", "/proc/neurowalk-run"),
    run("--out", "--out", ""),
    run("--out", "--out", "   "),
    run("--params", "--params", ""),
    run("KEY=VALUE", "--arena-opt", "novalue"),
    run("KEY=VALUE", "--arena-opt", "=1"),
    run("x", "--arena-opt", "x=1"),
    run("gap", "--arena", "box", "--arena-opt", "gap=1"),
    run("abc", "--arena", "box", "--arena-opt", "distance=abc"),
    run("distance", "--arena", "box", "--arena-opt", "distance=0.1"),
    run("distance", "--arena", "box", "--arena-opt", "distance=nan"),
    run("offset", "--arena", "box", "--arena-opt", "offset=inf"),
    run("width", "--arena", "box", "--arena-opt", "width=0"),
    run("angle", "--arena", "box", "--arena-opt", "angle=nan"),
    run("height", "--arena", "box", "--arena-opt", "height=-1"),
    run("step", "--arena", "climbing-track", "--arena-opt", "step=1"),
    run("wall_x", "--arena", "climbing-track", "--arena-opt", "wall_x=0"),
    run("height", "--arena", "cluttered", "--arena-opt", "height=0"),
    run("height", "--arena", "difficult", "--arena-opt", "height=nan"),
    run("width", "--arena", "complex-path", "--arena-opt", "width=5"),
    run("obstacle", "--arena", "complex-path", "--arena-opt", "obstacle=1"),
    run("spacing", "--arena", "complex-path", "--arena-opt", "spacing=0.1"),
    run("length", "--arena", "complex-path", "--arena-opt", "length=100"),
    run("angle", "--arena", "corner", "--arena-opt", "angle=5"),
    run("length", "--arena", "corner", "--arena-opt", "length=0.1"),
    run("gap", "--arena", "narrow-passage", "--arena-opt", "gap=-1"),
    run("width", "--arena", "narrow-passage", "--arena-opt", "width=0.1"),
    run("depth", "--arena", "narrow-passage", "--arena-opt", "depth=0.1"),
    run("funnel", "--arena", "narrow-passage", "--arena-opt", "funnel=80"),
    run("1.5", "--arena", "random", "--arena-opt", "n_boxes=1.5"),
    run("n_boxes", "--arena", "random", "--arena-opt", "n_boxes=61"),
    run("size", "--arena", "random", "--arena-opt", "size=0"),
    run("extent", "--arena", "random", "--arena-opt", "extent=1e9"),
    run("width", "--arena", "simple-deadlock", "--arena-opt", "width=0.2"),
    run("depth", "--arena", "simple-deadlock", "--arena-opt", "depth=0.5"),
    run("height", "--arena", "steps", "--arena-opt", "height=0.5"),
    run("distance", "--arena", "steps", "--arena-opt", "distance=0.1"),
    run("notjson", "--params", P_NOT_JSON),
    run("empty", "--params", P_EMPTY),
    run("list", "--params", P_LIST),
    run("params", "--params", P_NO_PARAMS),
    run("paramslist", "--params", P_PARAMS_LIST),
    run("speed", "--params", P_UNKNOWN),
    run("mu_b", "--params", P_NAN),
    run("mu_q", "--params", P_INF),
    run("gamma_b", "--params", P_HUGE),
    run("fast", "--params", P_STRING),
    run("True", "--params", P_BOOL),
    run("gamma_q", "--params", P_NEGATIVE),
    run("activity_cutoff", "--params", P_CUTOFF),
    run("tuned", "--params", P_TUNED),
    run("bogus", "--params", P_BOGUS_VARIANT),
    run("binary", "--params", P_BINARY),
    run("no-such-params", "--params", P_MISSING),
    run("a-folder", "--params", P_FOLDER),
    run("deep", "--params", P_DEEP),
]

# --- view (no output folder; the good folder must stay as it is all the same) ----------------------------------------

VIEW_CASES = [
    case("maze", "view", "--native", "--arena", "maze"),
    case("surrogate", "view", "--native", "--body", "surrogate"),
    case("size", "view", "--native", "--body-opt", "size=2"),
    case("steps", "view", "--native", "--steps", "0"),
    case("gallop", "view", "--native", "--gait", "gallop"),
    case("bogus", "view", "--native", "--variant", "bogus"),
    case("no-such-params", "view", "--native", "--params", P_MISSING),
    case("--steer", "view", "--native", "--controller", "fixed", "--steer", "3,3"),
    case("funnel", "view", "--native", "--arena", "narrow-passage", "--arena-opt", "funnel=nan"),
    case("--out", "view", "--out", GOOD),
    case("seed", "view", "--native", "--seed", "-2"),
    case("control_hz", "view", "--native", "--control-hz", "0"),
    case("reflexes", "view", "--native", "--body", "surrogate", "--reflexes"),
    case("backbone", "view", "--native", "--body", "surrogate", "--backbone"),
    case("reflexes", "view", "--native", "--body", "surrogate", "--climb"),
    case("drop", "view", GOOD, "--native"),
    case("--port", "run", "--web", "--port", "70000", "--out", GOOD),
    case("256.0.0.1", "run", "--web", "--host", "256.0.0.1", "--out", GOOD),
    case("RUN_DIR", "view"),
    case("run's folder", "view", FILES_DIR),
    case("--port", "view", GOOD, "--port", "0"),
    case("256.0.0.1", "view", GOOD, "--host", "256.0.0.1"),
    case("FILE.html", "view", GOOD, "--export", "replay.png"),
]

# --- figure ------------------------------------------------------------------------------------------------------


def fig(word: str, name: str, *args: str, xfail: str | None = None) -> Any:
    """A bad `neurowalk figure NAME` whose --out is the good folder (unless the case gives its own)."""
    out = () if "--out" in args else ("--out", GOOD)
    return case(word, "figure", name, *args, *out, xfail=xfail)


FIGURE_CASES = [
    fig("--seeds", "table1", "--seeds", "3"),
    fig("--control-hz", "fig2", "--control-hz", "27"),
    fig("control-hz", "fig8", "--quick", "--control-hz", "0"),
    fig("control-hz", "fig8", "--quick", "--control-hz", "nan"),
    fig("fast", "fig8", "--quick", "--control-hz", "fast"),
    fig("surrogate", "table2", "--quick", "--control-hz", "27"),
    fig("--workers", "fig2", "--workers", "2"),
    fig("workers", "fig8", "--quick", "--workers", "0"),
    fig("fig99", "fig99"),
    fig("fig99", "fig99", "--shared-runs", GOOD),
    fig("settings", "fig2", "--settings", "no-such-settings.json"),
    fig("settings", "fig2", "--settings", "no-such-settings.json", "--quick"),
    fig("''", ""),
    fig("FIG2", "FIG2"),
    fig("--seeds", "fig2", "--seeds", "3"),
    fig("--body", "fig2", "--body", "surrogate"),
    fig("--variant", "fig2", "--variant", "original"),
    fig("--gait", "fig2", "--gait", "wave"),
    fig("--video", "fig2", "--video"),
    fig("--arena-opt", "fig2", "--arena-opt", "size=1"),
    fig("--replot", "fig2", "--replot"),
    fig("--climb", "fig2", "--climb"),
    fig("seed", "fig2", "--seed", "-1"),
    fig("seven", "fig2", "--seed", "seven"),
    fig("seed", "fig3", "--quick", "--seed", str(2**63)),
    fig("fig99", "fig99", "--quick"),
    fig("--quick", "fig2", "--quick=yes"),
    fig("--seeds", "escape-map", "--seeds", "0"),
    fig("gallop", "escape-map", "--gait", "gallop"),
    fig("bogus", "escape-map", "--variant", "bogus"),
    fig("--seeds", "fig10", "--seeds", "-1"),
    fig("--gait", "fig10", "--gait", "tripod"),
    fig("--body", "fig3", "--body", "surrogate"),
    fig("gallop", "fig3", "--gait", "gallop"),
    fig("''", "fig3", "--gait", ""),
    fig("notjson", "fig4", "--params", P_NOT_JSON),
    fig("--params", "fig3", "--params", P_NOT_JSON),
    fig("--backend", "fig2", "--backend", "ray"),
    *(fig("--seed", name, "--seed", "-7") for name in sorted(FIGURES)),  # every figure, a new one too
    fig("--address", "fig3", "--address", "10.0.0.1:6379"),
    fig("--climb", "fig4", "--climb"),
    fig("bogus", "fig4", "--variant", "bogus"),
    fig("--variant", "fig4", "--variant", ""),
    fig("no-such-params", "fig4", "--params", P_MISSING),
    fig("x", "fig5", "--seeds", "x"),
    fig("binary", "fig8", "--params", P_BINARY),
    fig("wheels", "fig6", "--body", "wheels"),
    fig("size", "fig6", "--arena-opt", "size=0"),
    fig("size", "fig6", "--arena-opt", "size=nan"),
    fig("abc", "fig6", "--arena-opt", "size=abc"),
    fig("extent", "fig6", "--arena-opt", "extent=3"),
    fig("novalue", "fig6", "--arena-opt", "novalue"),
    fig("--climb", "fig6", "--climb"),
    fig("speed", "fig6", "--params", P_UNKNOWN),
    fig("--variant", "fig7", "--variant", "paper"),
    fig("summary.json", "fig7", "--out", f"{GOOD}/summary.json"),
    fig("--out", "fig2", "--out", ""),
    fig("--out", "fig4", "--out", " "),
    fig("--gait", "fig8", "--gait", "wave"),
    fig("summary.json", "fig8", "--out", f"{GOOD}/summary.json/fig8"),
    fig("--arena-opt", "fig9", "--arena-opt", "size=1"),
    fig("mu_b", "fig9", "--params", P_NAN),
    fig("--seeds", "latched-spin", "--seeds", "2"),
    fig("--body", "latched-spin", "--body", "surrogate"),
    fig("--variant", "steps", "--variant", "paper"),
    fig("--video", "steps", "--video"),
    fig("--video", "surrogate", "--video"),
    fig("--params", "surrogate", "--params", P_NAN),
    fig("--climb", "table2", "--climb", "--body", "surrogate"),
    fig("size", "table2", "--arena-opt", "size=100"),
    fig("wheels", "table2", "--body", "wheels"),
    fig("--seeds", "bodies", "--seeds", "0"),
    fig("--body", "bodies", "--body", "amosii"),
    fig("tuned", "table2", "--params", P_TUNED),
    fig("--bogus", "table2", "--bogus"),
]

# --- sweep: the grid options -----------------------------------------------------------------------------------------


def sweep(word: str, *args: str, xfail: str | None = None) -> Any:
    """A bad `neurowalk sweep` whose --out is the good folder (unless the case gives its own)."""
    out = () if "--out" in args else ("--out", GOOD)
    return case(word, "sweep", *args, *out, "--quiet", xfail=xfail)


SWEEP_CASES = [
    sweep("--control-hz", "--control-hz", "10,x"),
    sweep("control_hz", "--control-hz", "0"),
    sweep("maze", "--arena", "open,maze"),
    sweep("open,,box", "--arena", "open,,box"),
    sweep("wheeled", "--controller", "plastic,wheeled"),
    sweep("wheels", "--body", "wheels"),
    sweep("--arena", "--arena", ""),
    sweep("--controller", "--controller", ""),
    sweep("--body", "--body", ""),
    sweep("--gait", "--gait", ""),
    sweep("--variant", "--variant", ""),
    sweep("gallop", "--gait", "wave,gallop"),
    sweep("bogus", "--variant", "paper,bogus"),
    sweep("seeds", "--seeds", "0"),
    sweep("seeds", "--seeds", "-3"),
    sweep("seeds", "--seeds", str(10**30)),
    sweep("3,000,000,000 runs", "--seeds", "3000000000"),
    sweep("1,200,000 runs", "--arena", "open,box", "--seeds", "600000"),
    sweep("1,200,000 runs", "--arena-opt", "size=1,2,3", "--seeds", "400000", "--arena", "random"),
    sweep("100,000,000 steps", "--steps", "100000000", "--workers", "64"),
    sweep(str(10**30), "--steps", str(10**30)),
    sweep("--retries", "--retries", "-1"),
    sweep("--retries", "--retries", "one"),
    sweep("seed", "--seed-start", str(10**30)),
    sweep("many", "--seeds", "many"),
    sweep("seed-start", "--seed-start", "-1"),
    sweep("turn", "--body", "surrogate", "--body-opt", "turn=1,0"),
    sweep("turn", "--body", "surrogate", "--body-opt", "turn=nan"),
    sweep("--body-opt", "--body", "surrogate", "--body-opt", "turn"),
    sweep("speed", "--body", "amosii", "--body-opt", "speed=2"),
    sweep("seed", "--seed-start", str(2**63 - 1), "--seeds", "2"),
    sweep("steps", "--steps", "0"),
    sweep("steps", "--steps", "100000001"),
    sweep("1.5", "--steps", "1.5"),
    sweep("workers", "--workers", "0"),
    sweep("workers", "--workers", "-2"),
    sweep("--address", "--address", "ray://nowhere:10001"),
    sweep("dask", "--backend", "dask"),
    sweep("xml", "--export", "xml"),
    sweep("KEY=VALUE", "--arena-opt", "novalue"),
    sweep("gap", "--arena", "box", "--arena-opt", "gap=1"),
    sweep("distance", "--arena", "box,open", "--arena-opt", "distance=1"),
    sweep("distance", "--arena", "box", "--arena-opt", "distance=0.3,nan"),
    sweep("distance", "--arena", "box", "--arena-opt", "distance=1,"),
    sweep("n_boxes", "--arena", "random", "--arena-opt", "n_boxes=2,2.5"),
    sweep("distance", "--arena", "box,steps", "--arena-opt", "distance=0.2"),
    sweep("no-such-params", "--params", P_MISSING),
    sweep("speed", "--params", P_UNKNOWN),
    sweep("tripod", "--body", "surrogate", "--gait", "tripod"),
    sweep("--out", "--steps", "10", "--out"),
    sweep("summary.json", "--body", "surrogate", "--steps", "10", "--out", f"{GOOD}/summary.json"),
    sweep("summary.json", "--body", "surrogate", "--steps", "10", "--out", f"{GOOD}/summary.json/sweep"),
    sweep("--out", "--steps", "10", "--out", ""),
    case("--out", "sweep", "--steps", "10", "--out=\t"),
]

# --- sweep: the specs file, every EpisodeConfig field --------------------------------------------------------------

_SPEC_BASE = {"body": "surrogate", "steps": 10}
_spec_count = 0


def spec(word: str, line: dict | str, *, base: bool = True, xfail: str | None = None, shown: str = "") -> Any:
    """A sweep whose specs file holds a good spec, then a bad one: ``line`` (a dict on top of a good spec, or a raw
    line); ``shown``: what the test id shows instead of the line."""
    global _spec_count
    _spec_count += 1
    text = line if isinstance(line, str) else json.dumps({**(_SPEC_BASE if base else {}), **line})
    path = _file(f"specs-{_spec_count:03d}.jsonl", '{"body": "surrogate", "steps": 10}\n' + text + "\n")
    marks = [pytest.mark.xfail(reason=xfail, strict=True)] if xfail else []
    shown = shown or (text if isinstance(line, str) else json.dumps(line))
    return pytest.param(["sweep", "--specs", path, "--out", GOOD, "--quiet"], word, id=f"sweep spec {shown}",
                        marks=marks)  # fmt: skip


NAN, INF = float("nan"), float("inf")

SPEC_CASES = [
    spec("speed", {"speed": 1}),
    spec("body_opts", {"body": "wheeled", "body_opts": [1]}),
    spec("scale", {"body": "wheeled", "body_opts": {"scale": "big"}}),
    spec("scale", {"body": "wheeled", "body_opts": {"scale": 100}}),
    spec("scale", {"body": "amosii", "body_opts": {"scale": 0.5}}),
    spec("solver_iterations", {"body": "amosii", "body_opts": {"solver_iterations": 2.5}}),
    spec("timestep", {"body": "amosii", "body_opts": {"timestep": 0.5}}),
    spec("until", {"until": "trapped"}),
    spec("maze", {"arena": "maze"}),
    spec("3", {"arena": 3}),
    spec("None", {"arena": None}),
    spec("arena_opts", {"arena_opts": [1]}),
    spec("gap", {"arena": "box", "arena_opts": {"gap": 1}}),
    spec("wide", {"arena": "box", "arena_opts": {"width": "wide"}}),
    spec("distance", {"arena": "box", "arena_opts": {"distance": NAN}}),
    spec("offset", {"arena": "box", "arena_opts": {"offset": INF}}),
    spec("angle", {"arena": "box", "arena_opts": {"angle": True}}),
    spec("distance", {"arena": "box", "arena_opts": {"distance": 0.1}}),
    spec("n_boxes", {"arena": "random", "arena_opts": {"n_boxes": 2.5}}),
    spec("n_boxes", {"arena": "random", "arena_opts": {"n_boxes": 1e30}}),
    spec("x", {"arena": "open", "arena_opts": {"x": 1}}),
    spec("wheeled", {"controller": "wheeled"}),
    spec("7", {"controller": 7}),
    spec("steer", {"controller": "fixed", "steer": [2, 0]}),
    spec("steer", {"controller": "fixed", "steer": [1]}),
    spec("steer", {"controller": "fixed", "steer": [NAN, 0]}),
    spec("left", {"controller": "fixed", "steer": "left"}),
    spec("5", {"controller": "fixed", "steer": 5}),
    spec("steer", {"controller": "fixed", "steer": [True, False]}),
    spec("steer", {"controller": "plastic", "steer": [0, 0]}),
    spec("wheels", {"body": "wheels"}),
    spec("None", {"body": None}),
    spec("steps", {"steps": 0}),
    spec("steps", {"steps": -1}),
    spec("steps", {"steps": 1.5}),
    spec("steps", {"steps": "ten"}),
    spec("steps", {"steps": NAN}),
    spec("steps", {"steps": INF}),
    spec("steps", {"steps": True}),
    spec("steps", {"steps": 10**9}),
    spec("steps", {"steps": 10**400}),
    spec("steps", {"steps": None}),
    spec("seed", {"seed": -1}),
    spec("seed", {"seed": 2**63}),
    spec("seed", {"seed": 0.5}),
    spec("seed", {"seed": False}),
    spec("control_hz", {"control_hz": 0}),
    spec("control_hz", {"control_hz": -10}),
    spec("control_hz", {"control_hz": NAN}),
    spec("control_hz", {"control_hz": 1e9}),
    spec("control_hz", {"control_hz": -(10**400)}),
    spec("fast", {"control_hz": "fast"}),
    spec("control_hz", {"control_hz": 20}),
    spec("noise", {"noise": -0.1}),
    spec("noise", {"noise": 2}),
    spec("noise", {"noise": INF}),
    spec("noise", {"noise": True}),
    spec("b0", {"b0": -1}),
    spec("b0", {"b0": NAN}),
    spec("heavy", {"b0": "heavy"}),
    spec("b0", {"controller": "static", "b0": 1}),
    spec("q0", {"q0": -1}),
    spec("q0", {"q0": [1]}),
    spec("reflexes", {"reflexes": "yes"}),
    spec("reflexes", {"reflexes": 1}),
    spec("reflexes", {"reflexes": True}),
    spec("backbone", {"backbone": "no"}),
    spec("backbone", {"backbone": True}),
    spec("variant", {"variant": 3}),
    spec("bogus", {"variant": "bogus"}),
    spec("variant", {"variant": None}),
    spec("params", {"params": [0.01]}),
    spec("params", {"params": 5}),
    spec("params", {"params": []}),
    spec("params", {"params": 0}),
    spec("params", {"params": False}),
    spec("speed", {"params": {"speed": 1}}),
    spec("mu_b", {"params": {"mu_b": NAN}}),
    spec("mu_q", {"params": {"mu_q": "fast"}}),
    spec("gamma_b", {"params": {"gamma_b": -1}}),
    spec("k", {"params": {"k": True}}),
    spec("gait", {"gait": 5}),
    spec("gallop", {"gait": "gallop"}),
    spec("tripod", {"gait": "tripod"}),
    spec("not JSON", "{arena: box}"),
    spec("[1, 2]", "[1, 2]"),
    spec("null", "null"),
    spec("nested", "[" * 100_000, shown="[[[... nested 100000 deep"),
]


def specs_file(word: str, name: str, content: str | bytes, *extra: str) -> Any:
    return case(word, "sweep", "--specs", _file(name, content), *extra, "--out", GOOD, "--quiet")


SPECS_FILE_CASES = [
    case("no-such", "sweep", "--specs", f"{FILES_DIR}/no-such.jsonl", "--out", GOOD, "--quiet"),
    case("a-folder", "sweep", "--specs", P_FOLDER, "--out", GOOD, "--quiet"),
    case("--specs", "sweep", "--specs", " ", "--out", GOOD, "--quiet"),
    specs_file("empty", "specs-empty.jsonl", "# nothing\n\n"),
    specs_file("100,000,000 steps", "specs-long.jsonl", '{"steps": 100000000}\n', "--workers", "64"),
    specs_file("binary", "specs-binary.jsonl", b"\xff\xfe\x00\x81\n"),
    specs_file("--seeds", "specs-good.jsonl", '{"body": "surrogate", "steps": 10}\n', "--seeds", "3"),
    specs_file("--arena", "specs-good.jsonl", '{"body": "surrogate", "steps": 10}\n', "--arena", "box"),
    specs_file("--variant", "specs-good.jsonl", '{"body": "surrogate", "steps": 10}\n', "--variant", "paper"),
]

# --- calibrate, bench, arenas, export-model ------------------------------------------------------------------------

REPRODUCE_CASES = [
    case("nonsense", "reproduce", "--only", "fig2,nonsense", "--out", GOOD),
    case("result", "reproduce", "--only", "", "--out", GOOD),
    case("fig99", "reproduce", "--list", "--only", "fig99", "--out", GOOD),
    case("workers", "reproduce", "--quick", "--workers", "0", "--out", GOOD),
    case("--quick", "reproduce", "--quick=yes", "--out", GOOD),
    case("summary.json", "reproduce", "--quick", "--only", "fig2", "--out", f"{GOOD}/summary.json/rep"),
]

STUDY = _file(
    "tiny_study.py",
    "from neurowalk import EpisodeConfig, Plan, Study\n"
    "def runs(s):\n"
    "    for seed in range(s.n(2)):\n"
    "        yield Plan('plastic', EpisodeConfig(body='surrogate', steps=20, seed=s.seed + seed))\n"
    "study = Study('tiny', 'a tiny study', plot=print, runs=runs, measure=lambda s, r: {'n': len(r)})\n",
)
NO_STUDY = _file("no_study.py", "x = 1\n")


def study(word: str, file: str, *args: str) -> Any:
    """A bad `neurowalk study FILE` whose --out is the good folder (unless the case gives its own)."""
    out = () if "--out" in args else ("--out", GOOD)
    return case(word, "study", file, *args, *out)


#: Every setting a study of runs does not take by default, with a value: refused in one line naming the flag.
_REFUSED = {
    "--body": "surrogate",
    "--climb": None,
    "--variant": "paper",
    "--params": P_NOT_JSON,
    "--gait": "wave",
    "--video": None,
    "--arena-opt": "size=1",
    "--engine": "warp",
    "--device": "cpu",
    "--control-hz": "20",
}
STUDY_CASES = [
    study("no study file", f"{FILES_DIR}/none.py"),
    study("defines 0 studies", NO_STUDY),
    study("--seeds", STUDY, "--seeds", "0"),
    study("--seed", STUDY, "--seed", "-1"),
    study("--quick", STUDY, "--quick=yes"),
    study("--workers", STUDY, "--workers", "0"),
    study("unknown backend", STUDY, "--backend", "spark"),
    study("--address", STUDY, "--address"),
    study("--out", STUDY, "--out", ""),
    *(study(flag, STUDY, flag, *([v] if v else [])) for flag, v in _REFUSED.items()),
]  # fmt: skip

OTHER_CASES = [
    case("workers", "calibrate", "--workers", "0", "--out", f"{GOOD}/cal.json"),
    case("workers", "calibrate", "--workers", "-1", "--out", f"{GOOD}/cal.json"),
    case("two", "calibrate", "--workers", "two", "--out", f"{GOOD}/cal.json"),
    case("tank", "calibrate", "--body", "tank", "--out", f"{GOOD}/cal.json"),
    case("folder", "calibrate", "--quick", "--out", GOOD),
    case("summary.json", "calibrate", "--quick", "--out", f"{GOOD}/summary.json/cal.json"),
    case(
        "neurowalk-cal",
        "calibrate",
        "--quick",
        "--out",
        "/proc/neurowalk-cal.json",
    ),
    case("xxxx", "calibrate", "--out", f"{GOOD}/{'x' * 300}.json"),
    case("--grid", "calibrate", "--grid", "3", "--out", f"{GOOD}/cal.json"),
    case("--out", "calibrate", "--quick", "--out", ""),
    case("--out", "bench", "--quick", "--out", " "),
    case("--out", "export-model", "--out", ""),
    case("workers", "bench", "--workers", "0", "--out", GOOD),
    case("workers", "bench", "--workers", "-4", "--out", GOOD),
    case("1.5", "bench", "--workers", "1.5", "--out", GOOD),
    case("summary.json", "bench", "--quick", "--out", f"{GOOD}/summary.json"),
    case("summary.json", "bench", "--quick", "--out", f"{GOOD}/summary.json/bench"),
    case("neurowalk-bench", "bench", "--quick", "--out", "/proc/neurowalk-bench"),
    case("--quick", "bench", "--quick=yes", "--out", GOOD),
    case("box", "arenas", "box"),
    case("--all", "arenas", "--all"),
    case("--out", "export-model"),
    case("maze", "export-model", "--arena", "maze", "--out", f"{GOOD}/model.xml"),
    case("KEY=VALUE", "export-model", "--arena", "box", "--arena-opt", "distance", "--out", f"{GOOD}/model.xml"),
    case("distance", "export-model", "--arena", "box", "--arena-opt", "distance=-1", "--out", f"{GOOD}/model.xml"),
    case("n_boxes", "export-model", "--arena", "random", "--arena-opt", "n_boxes=-1", "--out", f"{GOOD}/m.xml"),
    case("distance", "export-model", "--arena", "steps", "--arena-opt", "distance=inf", "--out", f"{GOOD}/m.xml"),
    case(
        "60",
        "export-model",
        "--arena",
        "random",
        "--arena-opt",
        "n_boxes=60",
        "--arena-opt",
        "size=2",
        "--arena-opt",
        "extent=2",
        "--out",
        f"{GOOD}/m.xml",
    ),
    case("height", "export-model", "--arena", "cluttered", "--arena-opt", "height=-0.1", "--out", f"{GOOD}/m.xml"),
    case("folder", "export-model", "--out", GOOD),
    case("surrogate", "export-model", "--body", "surrogate", "--out", f"{GOOD}/m.xml"),
    case("tank", "export-model", "--body", "tank", "--out", f"{GOOD}/m.xml"),
    case("scale", "export-model", "--body", "wheeled", "--body-opt", "scale=-1", "--out", f"{GOOD}/m.xml"),
    case("summary.json", "export-model", "--out", f"{GOOD}/summary.json/model.xml"),
]

# --- optimize --------------------------------------------------------------------------------------------------------


def opt(word: str, *args: str, xfail: str | None = None) -> Any:
    """A bad `neurowalk optimize` whose --out is the good folder (unless the case gives its own)."""
    out = () if "--out" in args else ("--out", GOOD)
    return case(word, "optimize", "--quick", *args, *out, "--quiet", xfail=xfail)


OPTIMIZE_CASES = [
    opt("bogus", "--variant", "bogus"),
    opt("tuned", "--variant", "tuned"),
    opt("speed", "--fields", "mu_b,speed"),
    opt("''", "--fields", ""),
    opt("mu_b", "--fields", "mu_b,mu_b"),
    opt("mu_b", "--param", "mu_b=0.03:0.001"),
    opt("mu_b=a:b", "--param", "mu_b=a:b"),
    opt("mu_b", "--param", "mu_b=nan:0.1"),
    opt("mu_q", "--param", "mu_q=0:inf"),
    opt("gamma_b", "--param", "gamma_b=-1:0.1"),
    opt("=1:2", "--param", "=1:2"),
    opt("speed", "--param", "speed=0:1"),
    opt("mu_b=0.001", "--param", "mu_b=0.001"),
    opt("population", "--population", "1"),
    opt("generations", "--generations", "0"),
    opt("environments", "--environments", "-1"),
    opt("heldout", "--heldout", "0"),
    opt("steps", "--steps", "0"),
    opt("steps", "--steps", "1000000000"),
    opt("deadend_seeds", "--deadend-seeds", "0"),
    opt("2.5", "--generations", "2.5"),
    opt("seed", "--seed", "-1"),
    opt("seed", "--seed", str(2**32)),
    opt("train_seed", "--train-seed", str(2**63)),
    opt("heldout_seed", "--heldout-seed", str(2**63 - 10)),
    opt("environments", "--environments", str(10**30)),
    opt("train_seed", "--train-seed", "-5"),
    opt("heldout_seed", "--heldout-seed", "-5"),
    opt("overlap", "--train-seed", "0", "--heldout-seed", "0"),
    opt("sigma0", "--sigma0", "0"),
    opt("sigma0", "--sigma0", "2"),
    opt("sigma0", "--sigma0", "nan"),
    opt("sigma0", "--sigma0", "inf"),
    opt("wide", "--sigma0", "wide"),
    opt("workers", "--workers", "0"),
    opt("--address", "--address", "ray://nowhere:10001"),
    opt("spark", "--backend", "spark"),
    opt("summary.json", "--out", f"{GOOD}/summary.json"),
    opt("summary.json", "--out", f"{GOOD}/summary.json/search"),
    opt("xxxx", "--out", f"{GOOD}/{'x' * 300}"),
    opt("--out", "--out", ""),
]

# --- baseline --------------------------------------------------------------------------------------------------------


def base(word: str, *args: str) -> Any:
    """A bad `neurowalk baseline` whose --out is the good folder (unless the case gives its own)."""
    out = () if "--out" in args else ("--out", GOOD)
    return case(word, "baseline", "--quick", *args, *out, "--quiet")


BASELINE_CASES = [
    base("dqn", "--methods", "dqn"),
    base("''", "--methods", ""),
    base("PPO", "--methods", "neuroevo,PPO"),
    base("--generations", "--generations", "0"),
    base("--population", "--population", "1"),
    base("--envs", "--envs", "-3"),
    base("--ppo-steps", "--ppo-steps", "0"),
    base("--rppo-steps", "--rppo-steps", str(10**30)),
    base("--episode-steps", "--episode-steps", "0"),
    base("--eval-envs", "--eval-envs", "0"),
    base("--eval-envs", "--eval-envs", str(2**63)),
    base("--eval-steps", "--eval-steps", "-1"),
    base("2.5", "--eval-steps", "2.5"),
    base("--generations x --envs", "--generations", "5000", "--envs", "500"),
    base("--seed", "--seed", "-1"),
    base("--seed", "--seed", str(2**32)),
    base("summary.json", "--methods", "neuroevo", "--out", f"{GOOD}/summary.json"),
    base("xxxx", "--methods", "neuroevo", "--out", f"{GOOD}/{'x' * 300}"),
    base("--out", "--methods", "neuroevo", "--out", ""),
]

# --- the command line itself -----------------------------------------------------------------------------------------

TOP_CASES = [
    case("command", *[]),
    case("--bogus", "bodies", "--bogus"),
    case("walk", "walk"),
    case("Run", "Run"),
    case("--bogus", "--bogus", "run"),
]

# --- the physics engine: --engine / --device (with or without the warp extra installed) --------------------------

ENGINE_CASES = [
    case("gpu", "run", "--engine", "gpu", "--out", GOOD),
    case("--device", "run", "--device", "cpu", "--out", GOOD),
    case("amosii", "run", "--engine", "warp", "--body", "surrogate", "--out", GOOD),
    case("tpu", "sweep", "--engine", "tpu", "--out", GOOD),
    case("--device", "sweep", "--device", "cuda", "--out", GOOD),
    case("--engine", "figure", "fig6", "--engine", "warp", "--out", GOOD),
    case("--engine", "figure", "fig2", "--device", "cpu", "--out", GOOD),
    case("amosii", "figure", "table2", "--engine", "warp", "--body", "surrogate", "--out", GOOD),
    case("engine", "bench", "--engine", "wrap", "--out", GOOD),
    case("--device", "bench", "--device", "cpu", "--out", GOOD),
    case("--worlds", "bench", "--engine", "warp", "--worlds", "0", "--out", GOOD),
    case("--worlds", "bench", "--worlds", "64,many", "--out", GOOD),
    spec("engine", {"engine": "gpu"}),
    spec("engine", {"engine": 3}),
    spec("amosii", {"engine": "warp", "body": "wheeled"}),
]

CASES = [*TOP_CASES, *RUN_CASES, *VIEW_CASES, *FIGURE_CASES, *STUDY_CASES, *SWEEP_CASES, *SPEC_CASES, *SPECS_FILE_CASES,
         *REPRODUCE_CASES, *OTHER_CASES, *OPTIMIZE_CASES, *BASELINE_CASES, *ENGINE_CASES]  # fmt: skip


# --- fixtures --------------------------------------------------------------------------------------------------------


class WorkStartedError(BaseException):
    """Raised by the tripwires: a bad input reached real work (a BaseException: no ``except Exception`` hides it)."""


def _snapshot(folder: Path) -> dict[str, tuple[str, int]]:
    """{relative path: (sha256 of the bytes, mtime in ns)} of every file and folder under ``folder``."""
    out = {}
    for p in sorted(folder.rglob("*")):
        digest = hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else "folder"
        out[str(p.relative_to(folder))] = (digest, p.stat().st_mtime_ns)
    return out


@pytest.fixture(scope="module")
def places(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The good run folder (made once by a real run) and the folder of prepared input files."""
    good = tmp_path_factory.mktemp("good")
    assert main(["run", "--body", "surrogate", "--steps", "200", "--out", str(good), "--quiet"]) == 0
    assert {"summary.json", "trajectory.npz", "run.png"} <= {p.name for p in good.iterdir()}
    files = tmp_path_factory.mktemp("files")
    for name, content in FILES.items():
        (files / name).write_bytes(content if isinstance(content, bytes) else content.encode())
    (files / "a-folder").mkdir()
    return {"good": good, "files": files}


@pytest.fixture
def tripwires(places: dict[str, Path], monkeypatch: pytest.MonkeyPatch) -> None:
    """Replace the entry points of real work by functions that raise :class:`WorkStartedError`.

    Every module of the package is imported first: a module imported for the first time while the wires are in
    place would keep a wire for good (``from neurowalk.sim.episode import run_episode``), and later tests in the
    same process would run into it.
    """
    import neurowalk.body.registry
    import neurowalk.experiments.baselines.comparison
    import neurowalk.experiments.bench
    import neurowalk.experiments.calibration.calibrate
    import neurowalk.experiments.optimize.search
    import neurowalk.experiments.study
    import neurowalk.render
    import neurowalk.runners.store
    import neurowalk.runners.sweep
    import neurowalk.sim.episode
    from neurowalk.experiments import FIGURES, output

    for info in pkgutil.walk_packages(neurowalk.__path__, "neurowalk."):
        try:
            importlib.import_module(info.name)
        except ModuleNotFoundError as e:  # an optional extra that is not installed (e.g. mujoco_warp)
            if e.name is None or e.name.startswith("neurowalk"):
                raise

    def wire(what: str) -> Any:
        def tripped(*args: Any, **kwargs: Any) -> Any:
            raise WorkStartedError(what)

        return tripped

    for module, name in [
        (neurowalk.sim.episode, "run_episode"),
        (neurowalk.sim.episode, "build"),
        (neurowalk.runners.sweep, "run_sweep"),
        (neurowalk.runners.store, "ResultStore"),
        (neurowalk.experiments.calibration.calibrate, "calibrate"),
        (neurowalk.experiments.bench, "run_bench"),
        (neurowalk.body.registry, "body_xml"),
        (neurowalk.experiments.optimize.search, "new_state"),
        (neurowalk.experiments.optimize.search, "Runner"),
        (neurowalk.experiments.baselines.comparison, "run"),
        (neurowalk.experiments.study, "compute"),
        (neurowalk.render, "view"),
        (output, "load"),
        (output, "save_data"),
    ]:
        monkeypatch.setattr(module, name, wire(f"{module.__name__}.{name}"))
    monkeypatch.setattr(neurowalk.render, "has_display", lambda: True)  # view gets as far as it can
    for name, exp in FIGURES.items():
        monkeypatch.setitem(FIGURES, name, dataclasses.replace(exp, runs=wire(f"figure {name}")))  # where it begins


def _resolve(argv: list[str], places: dict[str, Path]) -> list[str]:
    return [a.replace(GOOD, str(places["good"])).replace(FILES_DIR, str(places["files"])) for a in argv]


@pytest.mark.parametrize("argv,word", CASES)
def test_bad_input_exits_2_with_one_line_before_any_work(argv, word, places, tripwires, capsys):
    before = _snapshot(places["good"])
    files_before = _snapshot(places["files"])
    status = main(_resolve(argv, places))
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert status == 2, captured.err
    assert len(lines) == 1 and lines[0].strip(), lines
    assert "Traceback" not in captured.err
    assert word in lines[0], (word, lines[0])
    assert _snapshot(places["good"]) == before
    assert _snapshot(places["files"]) == files_before


def _one_line_error(status: int, err: str, *words: str) -> None:
    lines = err.splitlines()
    assert status == 2 and len(lines) == 1 and "Traceback" not in err, err
    assert all(w in lines[0] for w in words), (words, lines[0])


def test_a_specs_file_larger_than_a_sweep_reads_is_refused_unread(places, tripwires, tmp_path, capsys):
    from neurowalk.cli.sweep import MAX_SPECS_BYTES

    big = tmp_path / "big.jsonl"
    with open(big, "wb") as f:
        f.truncate(MAX_SPECS_BYTES + 1)  # sparse: no disk used; reading it would take the memory
    status = main(["sweep", "--specs", str(big), "--out", str(places["good"]), "--quiet"])
    _one_line_error(status, capsys.readouterr().err, "big.jsonl", "MiB")


def test_the_runs_of_a_sweep_must_fit_in_the_machines_memory(places, tripwires, tmp_path, monkeypatch, capsys):
    from neurowalk.cli import sweep

    monkeypatch.setattr(sweep, "machine_memory", lambda: 10**9)  # 1 GB: 1,000,000 steps a run, on one worker
    out = ["--body", "surrogate", "--out", str(tmp_path / "s"), "--quiet"]
    status = main(["sweep", "--steps", "600000", "--workers", "2", *out])
    _one_line_error(status, capsys.readouterr().err, "600,000 steps", "2 at once", "1.2 GB", "1.0 GB")
    with pytest.raises(WorkStartedError):  # one worker: it fits
        main(["sweep", "--steps", "600000", "--workers", "1", *out])


def test_the_machines_memory_is_known_here():
    from neurowalk.cli.common import machine_memory

    have = machine_memory()
    assert have is None or 2**28 < have < 2**50


# --- figure --replot: damaged or foreign saved numbers ---------------------------------------------------------------


@pytest.fixture(scope="module")
def fig2_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder holding a real fig2 (quick): fig2.json, fig2.npz and fig2.png."""
    out = tmp_path_factory.mktemp("fig2")
    assert main(["figure", "fig2", "--quick", "--out", str(out)]) == 0
    return out


def _npy_as_npz(d: Path) -> None:
    import numpy as np

    np.save(d / "x.npy", np.zeros(3))
    (d / "x.npy").replace(d / "fig2.npz")


def _object_npz(d: Path) -> None:
    import numpy as np

    np.savez(d / "fig2.npz", a=np.array([{"x": 1}], dtype=object))


def _foreign(d: Path) -> None:
    (d / "fig2.json").write_text(json.dumps({"panel_a": [1, 2], "seed": 0}))


#: (name, what the damage does to a copy of a good fig2 folder, the file the error line must name).
REPLOT_DAMAGE = [
    ("garbage", lambda d: (d / "fig2.json").write_text("garbage {"), "fig2.json"),
    ("truncated", lambda d: (d / "fig2.json").write_bytes((d / "fig2.json").read_bytes()[:100]), "fig2.json"),
    ("binary", lambda d: (d / "fig2.json").write_bytes(b"\xff\xfe\x00\x81 not text"), "fig2.json"),
    ("empty", lambda d: (d / "fig2.json").write_text(""), "fig2.json"),
    ("empty object", lambda d: (d / "fig2.json").write_text("{}"), "fig2.json"),
    ("a list", lambda d: (d / "fig2.json").write_text("[1, 2]"), "fig2.json"),
    ("nested", lambda d: (d / "fig2.json").write_text("[" * 100_000), "fig2.json"),
    ("foreign", _foreign, "fig2.json"),
    ("npz missing", lambda d: (d / "fig2.npz").unlink(), "no fig2.npz"),
    ("npz garbage", lambda d: (d / "fig2.npz").write_text("junk"), "fig2.npz"),
    ("npz truncated", lambda d: (d / "fig2.npz").write_bytes((d / "fig2.npz").read_bytes()[:400]), "fig2.npz"),
    ("npz empty", lambda d: (d / "fig2.npz").write_bytes(b""), "fig2.npz"),
    ("npz of one array", _npy_as_npz, "fig2.npz"),
    ("npz of objects", _object_npz, "fig2.npz"),
    ("npz a folder", lambda d: ((d / "fig2.npz").unlink(), (d / "fig2.npz").mkdir()), "fig2.npz"),
]


@pytest.mark.parametrize("damage,names", [pytest.param(f, n, id=i) for i, f, n in REPLOT_DAMAGE])
def test_replot_of_damaged_or_foreign_numbers_exits_2_naming_the_file(damage, names, fig2_folder, tmp_path, capsys):
    import shutil

    d = tmp_path / "copy"
    shutil.copytree(fig2_folder, d)
    damage(d)
    before = _snapshot(d)
    status = main(["figure", "fig2", "--replot", "--out", str(d)])
    _one_line_error(status, capsys.readouterr().err, names, "without --replot")
    assert _snapshot(d) == before  # the files as they were; no picture drawn over the good one


def test_replot_of_good_numbers_draws_the_picture(fig2_folder, capsys):
    png = fig2_folder / "fig2.png"
    png.unlink()
    assert main(["figure", "fig2", "--replot", "--out", str(fig2_folder)]) == 0
    assert png.stat().st_size > 10_000 and not capsys.readouterr().err


# --- the list itself -------------------------------------------------------------------------------------------------


def _commands() -> dict[str, argparse.ArgumentParser]:
    """The subcommands of the parser: name -> its parser."""
    parser = cli.build_parser()
    (action,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(action.choices)


def _covered() -> dict[str, set[str]]:
    """What the cases touch: commands, figures, arena options (ARENA.KEY), spec fields, flags per command."""
    out: dict[str, set[str]] = {"command": set(), "figure": set(), "arena_opt": set(), "spec": set(), "flag": set()}
    for p in CASES:
        argv = p.values[0]
        if not argv or argv[0] not in _commands():
            continue
        command = argv[0]
        out["command"].add(command)
        if command == "figure":
            out["figure"].add(argv[1])
        out["flag"] |= {f"{command} {a.split('=')[0]}" for a in argv if a.startswith("--")}
        arenas = argv[argv.index("--arena") + 1].split(",") if "--arena" in argv else ["open"]
        for i, a in enumerate(argv[:-1]):
            if a == "--arena-opt" and "=" in argv[i + 1]:
                out["arena_opt"] |= {f"{arena}.{argv[i + 1].split('=')[0]}" for arena in arenas}
        if "--specs" in argv:
            name = argv[argv.index("--specs") + 1].removeprefix(f"{FILES_DIR}/")
            for line in str(FILES.get(name, "")).splitlines()[1:]:
                try:
                    s = json.loads(line)
                except (json.JSONDecodeError, RecursionError):
                    continue
                if isinstance(s, dict):
                    out["spec"] |= {k for k in s if k not in _SPEC_BASE or s[k] != _SPEC_BASE[k]}
                    if isinstance(s.get("arena_opts"), dict):
                        out["arena_opt"] |= {f"{s.get('arena', 'open')}.{k}" for k in s["arena_opts"]}
    return out


def test_the_list_is_long_distinct_and_touches_every_command():
    assert len(CASES) >= 120
    ids = [p.id for p in CASES]
    assert len(set(ids)) == len(ids), sorted(i for i in ids if ids.count(i) > 1)
    assert len({json.dumps(p.values[0]) for p in CASES}) == len(CASES)  # distinct inputs, not just distinct ids
    assert set(_commands()) <= _covered()["command"], "a command without fuzz cases"


def test_the_list_touches_every_figure_arena_option_spec_field_and_flag():
    from neurowalk.arenas import ARENAS, arena_options
    from neurowalk.experiments import FIGURES
    from neurowalk.runners.specs import FIELDS

    covered = _covered()
    assert set(FIGURES) <= covered["figure"]
    options = {f"{name}.{key}" for name in ARENAS for key in arena_options(name)}
    assert options <= covered["arena_opt"], sorted(options - covered["arena_opt"])
    assert set(FIELDS) <= covered["spec"], sorted(set(FIELDS) - covered["spec"])
    flags = {f"{name} {o}" for name, p in _commands().items() for a in p._actions for o in a.option_strings
             if o.startswith("--") and o not in ("--help", "--quiet")}  # fmt: skip
    assert flags <= covered["flag"], sorted(flags - covered["flag"])


def test_a_huge_worker_count_is_refused_in_one_line_by_every_command(capsys, tmp_path):
    """A 400-digit --workers is bad input (exit 2, one line), not an OverflowError deep in a command."""
    from neurowalk.cli import main

    huge = str(10**400)
    for argv in (["sweep", "--seeds", "1"], ["optimize"], ["calibrate"], ["bench"]):
        assert main([*argv, "--workers", huge, "--out", str(tmp_path / "o")]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert err == ["neurowalk: error: --workers must be at most 4,096, got a number of 401 digits"]
    assert not (tmp_path / "o").exists()


def test_an_option_given_as_dashes_or_an_empty_engine_is_one_line(capsys, tmp_path):
    """Found by the hypothesis fuzz: argparse reads `--variant=--` as an empty list; `--engine ''` names no engine."""
    from neurowalk.cli import main

    cases = {
        ("figure", "fig3", "--variant=--"): "neurowalk: error: --variant expects a value, got '--'",
        ("figure", "fig3", "--seeds=--"): "neurowalk: error: --seeds expects a value, got '--'",
        ("figure", "table2", "--engine", ""): "neurowalk: error: unknown engine ''; expected one of mujoco, "
        "mujoco.batch, warp",
    }
    for argv, line in cases.items():
        assert main([*argv, "--out", str(tmp_path / "o")]) == 2
        assert capsys.readouterr().err.strip().splitlines() == [line]
