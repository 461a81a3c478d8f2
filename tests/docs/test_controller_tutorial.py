"""The tutorial "Your own controller": its file, outside the package, runs unchanged on AMOSII (the CPU loop and
mujoco.batch, bit for bit), the wheeled robot, the surrogate, the command line and as a Gymnasium policy, with its
declared state recorded row for row; its bytes are part of its runs' code; a broken one is named in one line."""

from __future__ import annotations

import json
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest
from doc_blocks import blocks

from neurowalk import EpisodeConfig, run_episode
from neurowalk.cli import main
from neurowalk.controller import ControllerContractError, check_controller
from neurowalk.envs.explore import ExploreEnv
from neurowalk.envs.policy import ControllerPolicy, NetworkPolicy
from neurowalk.sim.check import check_engine
from neurowalk.sim.engines import ENGINES, PLANAR
from neurowalk.sim.trajectory import Trajectory

PAGE = "docs/tutorials/controller.md"


@pytest.fixture
def wary(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> str:
    """The page's controller file, saved as the reader saves it, in the folder the test runs in."""
    (block,) = [b for b in blocks(PAGE) if b.kind == "file" and b.why == "wary.py"]
    (tmp_path / "wary.py").write_text(block.code)
    monkeypatch.chdir(tmp_path)
    return "wary.py:Wary"


def _leaky(tr: Trajectory, leak: float = 0.9) -> np.ndarray:
    """The alarm the recorded inputs give through the file's filter (alarm_k = leak alarm_k-1 + (1 - leak) in_k)."""
    alarm, out = np.zeros(2), []
    for row in tr.inputs:
        alarm = leak * alarm + (1.0 - leak) * row
        out.append(alarm)
    return np.array(out)


@pytest.mark.parametrize("body", ["amosii", "wheeled", "surrogate"])
def test_the_file_runs_on_every_body_with_its_state_recorded_row_for_row(wary: str, body: str) -> None:
    ep = run_episode(EpisodeConfig(arena="corner", controller=wary, body=body, steps=400, seed=2))
    tr = ep.trajectory
    assert set(tr.state) == {"alarm"} and tr.state["alarm"].shape == (400, 2)
    np.testing.assert_allclose(tr.state["alarm"], _leaky(tr), rtol=0, atol=1e-12)  # the same step's row
    left, right = tr.state["alarm"].T
    alarmed = np.maximum(left, right) > 0.2
    assert alarmed.any()  # the corner comes within reach
    rule = np.where(alarmed[:, None], np.where((left >= right)[:, None], [1.0, -1.0], [-1.0, 1.0]), -1.0)
    np.testing.assert_array_equal(tr.outputs, rule)  # the steering recorded is the file's, of the same step


def test_mujoco_batch_steps_it_as_the_cpu_loop_does(wary: str) -> None:
    cfg = EpisodeConfig(arena="cluttered", controller=wary, steps=300, seed=1)
    cpu, threads = run_episode(cfg), run_episode(cfg.replace(engine="mujoco.batch"))
    for name, col in cpu.trajectory.arrays().items():
        np.testing.assert_array_equal(col, threads.trajectory.arrays()[name], err_msg=name)


def test_the_command_line_runs_it_and_keeps_its_state(wary: str, tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert main(["run", "--arena", "corner", "--controller", wary, "--steps", "300", "--out", str(out), "--quiet"]) == 0
    tr = Trajectory.load(out / "trajectory.npz")
    assert tr.state["alarm"].shape == (300, 2)
    np.testing.assert_allclose(tr.state["alarm"], _leaky(tr), rtol=0, atol=1e-12)
    assert json.loads((out / "summary.json").read_text())["controller"] == wary


def test_its_bytes_are_part_of_the_runs_code(wary: str, tmp_path: Path) -> None:
    """An edit of the file gives its runs another code (a store runs them again); the built-ins' code stays."""
    cfg = EpisodeConfig(arena="open", controller=wary, steps=20)
    before = run_episode(cfg).summary["code"]
    plain = run_episode(cfg.replace(controller="static")).summary["code"]
    path = tmp_path / "wary.py"
    path.write_text(path.read_text().replace("leak=0.9", "leak=0.8"))
    after = run_episode(cfg).summary["code"]
    assert before != after and run_episode(cfg.replace(controller="static")).summary["code"] == plain
    assert plain not in (before, after)


def test_as_a_policy_it_steers_as_the_network_policy_does() -> None:
    """ControllerPolicy of the built-in plastic controller steers Explore-v0 bit for bit as NetworkPolicy does: the
    policy shows the controller the environment's observation and acts with its steering."""
    actions = []
    for policy in (ControllerPolicy("plastic"), NetworkPolicy("plastic")):
        env = ExploreEnv(max_steps=2000)
        obs, _ = env.reset(seed=3)
        policy.reset()
        taken = []
        for _ in range(2000):
            a = policy(obs)
            taken.append(a)
            obs, *_ = env.step(a)
        actions.append(np.array(taken))
    np.testing.assert_array_equal(actions[0], actions[1])
    assert np.ptp(actions[0]) > 0.1  # it met something and steered


def test_the_user_file_runs_as_a_policy(wary: str) -> None:
    env = ExploreEnv(max_steps=200)
    obs, _ = env.reset(seed=0)
    policy = ControllerPolicy(wary)
    policy.reset()
    for _ in range(200):
        a = policy(obs)
        assert a.shape == (2,) and np.all(np.abs(a) <= 1)
        obs, *_ = env.step(a)


class _Broken:
    recorded: ClassVar[dict[str, tuple[int, ...]]] = {"gain": (3,)}

    def __init__(self) -> None:
        self.steering, self.gain = np.zeros(2), np.zeros(2)

    def reset(self, rng: np.random.Generator | None = None) -> None:
        pass

    def act(self, obs: object) -> np.ndarray:
        return np.zeros(19)


def test_check_controller_names_what_breaks_the_contract(wary: str) -> None:
    for name in ("plastic", "static", "braitenberg", wary):
        check_controller(name)
    with pytest.raises(ControllerContractError, match=r"^controller '_Broken': recorded 'gain' has shape \(2,\)"):
        check_controller(_Broken())


@pytest.mark.parametrize(
    "ref,text,line",
    [
        ("nowhere.py:Wary", None, "no such file 'nowhere.py'"),
        ("wary.py:Nope", None, "wary.py defines no 'Nope'"),
        ("bad.py:Wary", "class Wary:\n    def act(self\n", "bad.py, line 2: SyntaxError"),
        ("boom.py:Wary", "import numpy\nraise RuntimeError('no robot here')\n", "boom.py, line 2"),
    ],
)
def test_a_bad_controller_file_is_one_line_and_exit_2(wary: str, tmp_path: Path, capsys, ref, text, line) -> None:
    if text is not None:
        (tmp_path / ref.split(":")[0]).write_text(text)
    assert main(["run", "--controller", ref, "--steps", "10", "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and line in err, err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("engine", ["mujoco", "mujoco.batch", "planar"])
def test_every_cpu_engine_keeps_its_contract_with_the_file(wary: str, engine: str) -> None:
    """Deterministic, streamed as run, and (the CPU loop) resumed from a checkpoint of the user's controller's
    state to the same run bit for bit, its declared state included."""
    check_engine(PLANAR if engine == "planar" else ENGINES[engine], controller=wary)


@pytest.fixture
def hebbian(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> str:
    """The page's learning rule, saved as the reader saves it, in the folder the test runs in."""
    (block,) = [b for b in blocks(PAGE) if b.kind == "file" and b.why == "hebbian.py"]
    (tmp_path / "hebbian.py").write_text(block.code)
    monkeypatch.chdir(tmp_path)
    return "hebbian.py:hebbian"


def _eta(path: Path, eta: str) -> None:
    """Edit the rule's Hebbian rate, as a reader edits the file."""
    text = path.read_text()
    assert "ETA = 0.002" in text
    path.write_text(text.replace("ETA = 0.002", f"ETA = {eta}"))


@pytest.mark.parametrize("body,steps", [("surrogate", 3000), ("amosii", 300)])
def test_a_rule_that_adds_nothing_is_the_papers_network_and_an_edit_reaches_it(
    hebbian: str, tmp_path: Path, body: str, steps: int
) -> None:
    """With its Hebbian rate 0 the file's rule is the paper's step: the run (stepped a step at a time through the
    file's function) is the compiled paper network's, every column bit for bit; with its rate > 0 the weights b rise
    above the paper's where they first part. The file is edited in this process: the edit reaches the compiled rule."""
    cfg = EpisodeConfig(arena="corner", body=body, steps=steps, seed=4)
    paper = run_episode(cfg).trajectory
    hebb = run_episode(cfg.replace(variant=hebbian)).trajectory
    first = np.flatnonzero(np.any(hebb.b != paper.b, axis=1))[0]  # the first step the two differ at: the same inputs
    assert np.all(hebb.b[first] >= paper.b[first]) and np.any(hebb.b[first] > paper.b[first])  # the term adds to b
    _eta(tmp_path / "hebbian.py", "0.0")
    same = run_episode(cfg.replace(variant=hebbian)).trajectory
    for name, col in paper.arrays().items():
        np.testing.assert_array_equal(col, same.arrays()[name], err_msg=name)


def test_mujoco_batch_steps_the_rule_as_the_cpu_loop_does(hebbian: str) -> None:
    cfg = EpisodeConfig(arena="cluttered", variant=hebbian, steps=200, seed=1)
    cpu, threads = run_episode(cfg), run_episode(cfg.replace(engine="mujoco.batch"))
    for name, col in cpu.trajectory.arrays().items():
        np.testing.assert_array_equal(col, threads.trajectory.arrays()[name], err_msg=name)


def test_table2_has_the_rules_row_and_its_store_reruns_it_on_an_edit(hebbian: str, tmp_path: Path, capsys) -> None:
    """The rule's row beside the paper's; the command again takes its runs from the store, and after an edit of the
    file runs them again (the store's code holds the file's bytes)."""
    out = tmp_path / "table2"
    args = ["figure", "table2", "--variant", hebbian, "--quick", "--seeds", "2", "--out", str(out)]
    assert main(args) == 0 and main(args) == 0
    assert "going on from the 10 finished runs" in capsys.readouterr().out
    _eta(tmp_path / "hebbian.py", "0.001")
    assert main(args) == 0
    assert "made by other code" in capsys.readouterr().out
    counts = json.loads((out / "table2.json").read_text())["counts"]
    assert f"plastic ({hebbian})" in counts and "plastic-paper" in counts
    assert counts[f"plastic ({hebbian})"]["success"] + counts[f"plastic ({hebbian})"]["failure"] == 2
    assert EpisodeConfig(variant=hebbian).files() == (Path("hebbian.py"),)


@pytest.mark.parametrize(
    "text,line",
    [
        ("BASE = 'nope'\ndef rule(s, i1, i2, p):\n    pass\n", "BASE must be 'paper' or 'original'"),
        ("rule = 3\n", "is a int, not a function"),
    ],
)
def test_a_bad_rule_file_is_one_line_and_exit_2(tmp_path: Path, monkeypatch, capsys, text: str, line: str) -> None:
    (tmp_path / "bad.py").write_text(text)
    monkeypatch.chdir(tmp_path)
    assert main(["run", "--variant", "bad.py:rule", "--steps", "10", "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and line in err, err
    assert not (tmp_path / "out").exists()


def test_a_sweep_runs_it_on_a_pool_and_runs_it_again_after_an_edit(wary: str, tmp_path: Path) -> None:
    """A grid over the user's controller and a built-in, on a pool of two workers (each loads the file); the same
    sweep again runs nothing, and after an edit of the file its store runs them all again."""
    out = tmp_path / "sweep"
    argv = ["sweep", "--arena", "corner", "--body", "surrogate", "--controller", f"{wary},plastic", "--seeds", "2",
            "--steps", "200", "--workers", "2", "--out", str(out), "--quiet"]  # fmt: skip
    counts = []
    for edit in (None, None, "leak=0.8"):
        if edit is not None:
            path = tmp_path / "wary.py"
            path.write_text(path.read_text().replace("leak=0.9", edit))
        assert main(argv) == 0
        info = json.loads((out / "sweep.json").read_text())
        counts.append((info["counts"]["ok"], info["counts"]["skipped"]))
    assert counts == [(4, 0), (0, 4), (4, 0)]


def test_a_study_file_runs_it_beside_a_built_in(wary: str, tmp_path: Path) -> None:
    (tmp_path / "duel.py").write_text(
        "import matplotlib.pyplot as plt\n"
        "from neurowalk import EpisodeConfig, Plan, Study\n\n"
        "def runs(s):\n"
        f"    for c in ({wary!r}, 'plastic'):\n"
        "        cfg = EpisodeConfig(arena='corner', body='surrogate', controller=c, steps=300, seed=s.seed)\n"
        "        yield Plan(c, cfg)\n\n"
        "def measure(s, results):\n"
        "    return {c: results[c][0].path_length_m for c in results}\n\n"
        "def plot(result):\n"
        "    fig, ax = plt.subplots()\n"
        "    ax.bar(list(result.summary), list(result.summary.values()))\n"
        "    return fig\n\n"
        "study = Study('duel', 'a user controller beside the plastic network', plot=plot, runs=runs, measure=measure)\n"
    )
    out = tmp_path / "duel"
    assert main(["study", "duel.py", "--out", str(out)]) == 0
    summary = json.loads((out / "duel.json").read_text())
    assert set(summary) >= {wary, "plastic"} and all(summary[c] > 0 for c in (wary, "plastic"))
