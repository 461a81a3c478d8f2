"""The regression list (issue 27): runs over every engine, body, arena family, variant, climbing, a sweep, figures'
json and Gymnasium rollouts, each reduced to one sha256 of its outputs, and to what of it holds on any CPU.

A redesign must reproduce every hash: the CLI, spec keys, file formats and stored results stay as they are. What
is hashed is what a user keeps: a run's ``trajectory.npz`` arrays and ``summary.json`` (less the wall-clock fields),
a sweep's stored results, a figure's json, an environment's observations and rewards, an exported MJCF.

The hash holds bit for bit only where the floating point is the same: the same numpy, MuJoCo and numba, and the
same CPU type (numba compiles for the host CPU; numpy picks its SIMD kernels, and its OpenBLAS its kernels, when
they load), which :func:`fingerprint` names. Each case also gives what holds on any x86 machine
(:class:`Result`): the first :data:`HEAD` rows of its floating-point arrays, which agree to a tolerance
(``test_regression.py`` argues it), and its outcome-level values (escaped, trapped, wedged periods, a sweep's
counts), which agree exactly.

``hashes.json`` beside this file holds the recorded hashes, outcomes and fingerprint, ``heads.npz`` the heads;
record them again with ``python tests/regression/record.py`` only where a change of results is intended (and say
so).
"""

from __future__ import annotations

import hashlib
import json
import platform
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

#: Fields of a summary that measure the machine, not the run.
VOLATILE = {"wall_time_s", "real_time_factor", "neurowalk_version", "code", "resumed_at_step"}
#: Rows of each floating-point array compared on any CPU (the first 5 s of a run at 10 Hz).
HEAD = 50
#: A run's outcome-level values: what a figure counts.
OUTCOME_KEYS = ("completed", "steps", "escaped", "trapped", "ever_trapped", "wedged_periods")


def fingerprint() -> dict[str, Any]:
    """What the hashes' bits depend on: the versions of numpy, MuJoCo, numba and Python, and the CPU as each of
    them uses it (:func:`neurowalk.cpu.cpu_fingerprint`)."""
    import mujoco
    import numba

    from neurowalk.cpu import cpu_fingerprint

    return {
        "numpy": np.__version__,
        "mujoco": mujoco.__version__,
        "numba": numba.__version__,
        "machine": platform.machine(),
        "python": ".".join(platform.python_version_tuple()[:2]),
        **cpu_fingerprint(),
    }


@dataclass
class Result:
    """A case's outputs: ``sha256`` of all of them; ``head``: name -> the first :data:`HEAD` rows of a
    floating-point array; ``outcome``: JSON values that must agree exactly on any CPU."""

    sha256: str
    head: dict[str, np.ndarray] = field(default_factory=dict)
    outcome: dict[str, Any] = field(default_factory=dict)


class Digest:
    """A sha256 fed with named arrays and JSON values in a canonical form."""

    def __init__(self) -> None:
        self.h = hashlib.sha256()

    def array(self, name: str, a: np.ndarray) -> None:
        a = np.ascontiguousarray(a)
        self.h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        self.h.update(a.tobytes())

    def value(self, name: str, v: Any) -> None:
        self.h.update(f"{name}|{json.dumps(v, sort_keys=True, allow_nan=True)}|".encode())

    def hexdigest(self) -> str:
        return self.h.hexdigest()


def _summary(d: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in d.items() if k not in VOLATILE}


def _outcome(summary: dict[str, Any]) -> dict[str, Any]:
    return {k: summary[k] for k in OUTCOME_KEYS if k in summary}


#: The arrays of a run whose heads are compared: where it is, what it senses, what its network does.
HEAD_ARRAYS = ("pose", "inputs", "outputs", "b", "q")


def _run_folder(out: Path) -> Result:
    """A run's folder: its trajectory's arrays and its summary."""
    dig = Digest()
    head = {}
    with np.load(out / "trajectory.npz", allow_pickle=False) as z:
        for name in sorted(z.files):
            dig.array(name, z[name])
            if name in HEAD_ARRAYS:
                head[name] = z[name][:HEAD]
    summary = json.loads((out / "summary.json").read_text())
    dig.value("summary", _summary(summary))
    return Result(dig.hexdigest(), head, _outcome(summary))


def _cli(args: list[str]) -> None:
    from neurowalk.cli import main

    code = main(args)
    if code != 0:
        raise RuntimeError(f"neurowalk {' '.join(args)} exited {code}")


def _run(*args: str) -> Callable[[Path], Result]:
    def case(tmp: Path) -> Result:
        _cli(["run", *args, "--quiet", "--out", str(tmp / "run")])
        return _run_folder(tmp / "run")

    return case


def _numbers(v: Any, path: str, out: dict[str, list[float]]) -> Any:
    """``v`` with its floats taken out into ``out`` (by the path of the list or object that holds them)."""
    if isinstance(v, float):
        out.setdefault(path, []).append(v)
        return "<float>"
    if isinstance(v, dict):
        return {k: _numbers(x, f"{path}/{k}", out) for k, x in v.items()}
    if isinstance(v, list):
        return [_numbers(x, path, out) for x in v]
    return v


def _figure(name: str, *args: str) -> Callable[[Path], Result]:
    def case(tmp: Path) -> Result:
        _cli(["figure", name, "--quick", *args, "--out", str(tmp / name)])
        dig = Digest()
        data = json.loads((tmp / name / f"{name}.json").read_text())
        data = {k: v for k, v in data.items() if "wall" not in k and k not in ("store", "code", "quick")}
        dig.value("json", data)
        floats: dict[str, list[float]] = {}
        shape = _numbers(data, "", floats)  # every bool, int, string and the json's shape: exact anywhere
        return Result(dig.hexdigest(), {k: np.array(v) for k, v in floats.items()}, {"json": shape})

    return case


def _sweep(tmp: Path) -> Result:
    from neurowalk.runners.store import ResultStore

    _cli(["sweep", "--body", "surrogate", "--arena", "box,corner", "--controller", "plastic,static", "--seeds", "2",
          "--steps", "2000", "--workers", "2", "--quiet", "--out", str(tmp / "sweep")])  # fmt: skip
    with ResultStore(tmp / "sweep" / "results.sqlite") as store:
        results = store.results()
    dig = Digest()
    for key in sorted(results):
        dig.value(key, _summary(results[key]))
    counts: dict[str, int] = {}
    for s in results.values():
        for k in ("escaped", "trapped", "ever_trapped"):
            name = f"{s['arena']}/{s['controller']}/{k}"
            counts[name] = counts.get(name, 0) + (s[k] is True)
    return Result(dig.hexdigest(), {}, {"runs": len(results), "counts": dict(sorted(counts.items()))})


def _batch(tmp: Path) -> Result:
    from neurowalk.sim.batch import run_batch
    from neurowalk.sim.episode import EpisodeConfig

    cfgs = [EpisodeConfig(arena="cluttered", steps=200, seed=s) for s in (0, 1)]
    dig, res = Digest(), Result("")
    for i, ep in enumerate(run_batch(cfgs, nthread=2, progress=False)):
        for name in ("t", "pose", "outputs", "b", "q", "targets", "qpos"):
            dig.array(f"{i}/{name}", getattr(ep.trajectory, name))
        for name in HEAD_ARRAYS:
            res.head[f"{i}/{name}"] = getattr(ep.trajectory, name)[:HEAD]
        dig.value(f"{i}/summary", _summary(ep.summary))
        res.outcome[str(i)] = _outcome(ep.summary)
    res.sha256 = dig.hexdigest()
    return res


def _gym(env_id: str, steps: int) -> Callable[[Path], Result]:
    def case(tmp: Path) -> Result:
        import gymnasium

        import neurowalk.envs  # noqa: F401  (registers the environments)

        env = gymnasium.make(env_id)
        obs, _ = env.reset(seed=3)
        rng = np.random.default_rng(0)
        dig = Digest()
        dig.array("obs0", np.asarray(obs))
        observations, rewards, ends = [np.asarray(obs, dtype=float)], [], []
        for k in range(steps):
            obs, reward, term, trunc, _ = env.step(rng.uniform(-1, 1, size=2))
            dig.array(f"{k}/obs", np.asarray(obs))
            dig.value(f"{k}/r", [float(reward), bool(term), bool(trunc)])
            observations.append(np.asarray(obs, dtype=float))
            rewards.append(float(reward))
            ends.append([bool(term), bool(trunc)])
        env.close()
        head = {"obs": np.array(observations)[:HEAD], "reward": np.array(rewards)[:HEAD]}
        return Result(dig.hexdigest(), head, {"ends": ends})

    return case


def _text(tmp: Path, texts: dict[str, str]) -> Result:
    """Texts made without floating-point arithmetic that a CPU could round otherwise: exact anywhere."""
    dig = Digest()
    for name, text in texts.items():
        dig.value(name, text)
    return Result(dig.hexdigest(), {}, {"sha256": dig.hexdigest()})


def _export(tmp: Path) -> Result:
    _cli(["export-model", "--arena", "difficult", "--out", str(tmp / "model.xml")])
    return _text(tmp, {"xml": (tmp / "model.xml").read_text()})


def _arenas(tmp: Path) -> Result:
    from neurowalk.arenas import make_arena

    texts = {}
    for name, opts in [("random", {"n_boxes": 12, "extent": 3.0}), ("complex-path", {}), ("steps", {}),
                       ("climbing-track", {})]:  # fmt: skip
        texts[name] = make_arena(name, **opts).to_mjcf()
    return _text(tmp, texts)


def _sensory(tmp: Path) -> Result:
    from neurowalk.neural.sensory import simulate

    inputs = np.clip(np.random.default_rng(1).normal(0, 0.7, (400, 2)), -1, 1)
    dig, head = Digest(), {}
    for mode in ("plastic", "static", "braitenberg"):
        tr = simulate(inputs, mode=mode)
        for name in ("outputs", "b", "q"):
            dig.array(f"{mode}/{name}", getattr(tr, name))
            head[f"{mode}/{name}"] = getattr(tr, name)[:HEAD]
    return Result(dig.hexdigest(), head)


#: name -> case(tmp folder) -> its :class:`Result`.
CASES: dict[str, Callable[[Path], Result]] = {
    "run-amosii-open": _run("--arena", "open", "--steps", "200"),
    "run-amosii-box": _run("--arena", "box", "--steps", "300"),
    "run-amosii-simple-deadlock": _run("--arena", "simple-deadlock", "--steps", "300"),
    "run-amosii-narrow-passage": _run("--arena", "narrow-passage", "--steps", "300"),
    "run-amosii-corner": _run("--arena", "corner", "--steps", "300"),
    "run-amosii-cluttered-climb": _run("--arena", "cluttered", "--climb", "--steps", "200"),
    "run-amosii-steps-climb": _run("--arena", "steps", "--climb", "--steps", "200"),
    "run-amosii-difficult-original": _run("--arena", "difficult", "--variant", "original", "--steps", "300"),
    "run-amosii-box-static": _run("--arena", "box", "--controller", "static", "--steps", "300"),
    "run-amosii-box-braitenberg": _run("--arena", "box", "--controller", "braitenberg", "--steps", "300"),
    "run-amosii-fixed-turn": _run("--arena", "open", "--controller", "fixed", "--steer", "-1,1", "--steps", "200"),
    "run-amosii-tripod": _run("--arena", "open", "--gait", "tripod", "--steps", "200"),
    "run-amosii-random": _run("--arena", "random", "--arena-opt", "n_boxes=6", "--seed", "4", "--steps", "300"),
    "run-amosii-complex-path": _run("--arena", "complex-path", "--steps", "200"),
    "run-wheeled-box": _run("--body", "wheeled", "--arena", "box", "--steps", "300"),
    "run-wheeled-half-cluttered": _run(
        "--body", "wheeled", "--body-opt", "scale=0.5", "--arena", "cluttered", "--steps", "300"
    ),
    "run-surrogate-random": _run("--body", "surrogate", "--arena", "random", "--seed", "2", "--steps", "5000"),
    "run-surrogate-difficult-original": _run(
        "--body", "surrogate", "--arena", "difficult", "--variant", "original", "--steps", "5000"
    ),
    "run-surrogate-corner-static": _run(
        "--body", "surrogate", "--arena", "corner", "--controller", "static", "--steps", "3000"
    ),
    "run-surrogate-fast": _run("--body", "surrogate", "--body-opt", "speed=1.5", "--arena", "box", "--steps", "3000"),
    "run-surrogate-wheeled": _run("--body", "surrogate-wheeled", "--arena", "cluttered", "--steps", "5000"),
    "batch-mujoco": _batch,
    "sweep-surrogate": _sweep,
    "figure-fig2": _figure("fig2"),
    "figure-fig4": _figure("fig4"),
    "gym-explore": _gym("neurowalk/Explore-v0", 200),
    "gym-explore-physics": _gym("neurowalk/ExplorePhysics-v0", 30),
    "export-model": _export,
    "arenas-mjcf": _arenas,
    "sensory-simulate": _sensory,
}
