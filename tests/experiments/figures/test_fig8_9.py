"""Fig. 8 (narrow passage) and Fig. 9 (complex path): outcome rules, resumable store, smoke runs of both figures."""

import json

import numpy as np
import pytest

from neurowalk.arenas import make_arena
from neurowalk.arenas.generated import MOUTH, OPENING
from neurowalk.cli import main
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import fig8, fig9
from neurowalk.experiments.suites.real_robot import (
    camera_view,
    make_spec,
    path_every,
    run_store_paths,
    sampled,
    snapshot_rows,
    video_every,
)
from neurowalk.experiments.suites.timing import steps_for


def test_both_figures_are_registered_with_the_options_the_cli_passes():
    for name in ("fig8", "fig9"):
        assert {"seeds", "video", "variant", "params", "control_hz", "workers"} <= set(FIGURES[name].takes)
        assert FIGURES[name].keeps_runs


def test_specs_carry_the_network_variant_and_overrides():
    s = make_spec(Settings(variant="original", params={"a": 4.0}), "narrow-passage", {}, "static", 3, 100)
    assert s["controller"] == "static" and s["seed"] == 3 and s["steps"] == 100
    assert s["variant"] == "original" and s["params"] == {"a": 4.0}
    assert "params" not in make_spec(Settings(), "narrow-passage", {}, "plastic", 0, 100)
    at27 = make_spec(Settings(control_hz=27), "narrow-passage", {}, "static", 3, 100)
    assert s["control_hz"] == 10.0 and at27["control_hz"] == 27 and at27["variant"] == "paper"


class _StopError(Exception):
    pass


@pytest.mark.parametrize(
    "fig,quick,seconds", [(fig8, True, fig8.QUICK_S), (fig8, False, fig8.RUN_S), (fig9, True, fig9.QUICK_S)]
)
@pytest.mark.parametrize("hz", [10.0, 27.0])
def test_runs_last_their_seconds_at_the_figures_control_rate(monkeypatch, tmp_path, fig, quick, seconds, hz):
    seen = []

    def store(specs, folder, workers):
        seen.extend(specs)
        raise _StopError

    monkeypatch.setattr(fig, "run_store_paths", store)
    with pytest.raises(_StopError):
        fig.run(Settings(quick=quick, seeds=2, out=tmp_path, control_hz=hz))
    assert seen and all(s["control_hz"] == hz for s in seen)
    assert {s["steps"] for s in seen} == {round(seconds * hz)}
    if hz == 10.0:  # the runs of the 10 Hz figures, to the step (quick runs as long, with fewer seeds)
        assert seen[0]["steps"] == {fig8.RUN_S: 5000, fig9.PATH_S: 8000}[seconds]


def test_path_points_and_video_frames_are_spaced_in_seconds():
    assert path_every(10.0) == 10 and path_every(27.0) == 27  # 1 s
    assert video_every(10.0) == 4 and video_every(27.0) == 11  # 0.4 s of simulated time a frame


def test_snapshot_rows_end_where_the_robot_got_out():
    assert list(snapshot_rows(1000, 500, 6)) == [0, 100, 200, 300, 400, 500]
    assert snapshot_rows(1000, None, 6)[-1] == 999
    assert list(sampled(np.arange(25)[:, None], 10)[:, 0]) == [0, 10, 20, 24]


def test_camera_frames_the_whole_path_and_the_start():
    v = camera_view(make_arena("complex-path"), aspect=16 / 9)
    assert 1.0 < v["lookat"][0] < 2.5 and v["distance"] > 2.0


@pytest.mark.parametrize(
    "xy,label,row",
    [
        ([[0, 0], [1.0, 0.1], [3.0, 0.3], [3.0, 1.0]], fig9.OUT_LEFT, 3),
        ([[0, 0], [0.5, 0], [-0.1, 0], [-0.4, 0]], fig9.OUT_END, 3),
        ([[0, 0], [0.2, -0.3], [0.1, -0.7]], fig9.OUT_END, 2),  # round the right wall's start
        ([[0, 0], [1.0, 0.0], [MOUTH + 3.0 - OPENING + 0.1, 0.0], [2.0, 0.0]], fig9.STUCK_END, None),
        ([[0, 0], [1.0, 0.0], [1.2, 0.05]], fig9.STUCK_PATH, None),
    ],
)
def test_fig9_outcome_rule(xy, label, row):
    assert fig9.outcome(np.asarray(xy, dtype=float), make_arena("complex-path")) == (label, row)


def test_store_resumes_instead_of_rerunning(tmp_path):
    from neurowalk.runners.store import ResultStore

    specs = [make_spec(Settings(), "narrow-passage", {}, net, 0, 30) for net in ("plastic", "static")]
    first = run_store_paths(specs, tmp_path, workers=1)
    with ResultStore(tmp_path / "results.sqlite") as store:
        before = {r["key"]: r["finished_at"] for r in store.rows()}
    more = [*specs, make_spec(Settings(), "narrow-passage", {}, "plastic", 1, 30)]
    again = run_store_paths(more, tmp_path, workers=1)
    with ResultStore(tmp_path / "results.sqlite") as store:
        after = {r["key"]: r["finished_at"] for r in store.rows()}
    assert len(after) == 3 and all(after[k] == t for k, t in before.items())  # the first two were not rerun
    assert all(again[k] == v for k, v in first.items())
    assert all(len(r["path"]) == 4 for r in again.values())  # rows 0, 10, 20 and the last (29)


def _check_strip_and_paths(s: dict, a: dict, seeds: int) -> None:
    for net in ("plastic", "static"):
        frames = a[f"{net}/frames"]
        assert frames.ndim == 4 and frames.shape[-1] == 3 and frames.dtype == np.uint8
        assert frames.std() > 5  # a rendered scene, not a blank image
        assert (
            len(a[f"{net}/snapshot_t"]) == len(frames) and a[f"{net}/snapshot_t"][0] < 0.15
        )  # row 0: after the first step
        for k in range(seeds):
            assert a[f"{net}/path/{k}"].shape[1] == 2
        assert len(s["counts"][net]["runs"]) == seeds
    assert s["rule"] and s["geometry"]["boxes"] and s["body"] == "amosii"


def test_fig8_quick_from_the_command_line_then_replot(tmp_path):
    assert main(["figure", "fig8", "--quick", "--seeds", "1", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "fig8.json").read_text())
    with np.load(tmp_path / "fig8.npz") as z:
        a = {k: z[k] for k in z.files}
    _check_strip_and_paths(s, a, 1)
    assert s["steps"] == steps_for(fig8.QUICK_S, 10.0) == 5000 and s["seeds"] == 1
    assert s["control_hz"] == 10.0 and s["duration_s"] == fig8.QUICK_S
    rr = s["real_robot"]
    assert rr["events"]["escaped"]["paper_s"] == 50.0 and not rr["same_clock"] and rr["note"]
    for net in ("plastic", "static"):
        c = s["counts"][net]
        assert c["escaped"] == sum(r["escaped"] for r in c["runs"]) and s["escaped"][net] == f"{c['escaped']}/1"
        assert a[f"{net}/path/0"][0] == pytest.approx([0.0, 0.0], abs=0.02)
        assert s["example"][net]["escaped"] == c["runs"][0]["escaped"]  # the example reruns the stored seed
    png = (tmp_path / "fig8.png").stat().st_mtime_ns
    assert main(["figure", "fig8", "--replot", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "fig8.png").stat().st_mtime_ns >= png and (tmp_path / "fig8.png").stat().st_size > 50_000


def test_fig9_quick_from_the_command_line(tmp_path):
    assert main(["figure", "fig9", "--quick", "--seeds", "1", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "fig9.json").read_text())
    with np.load(tmp_path / "fig9.npz") as z:
        a = {k: z[k] for k in z.files}
    _check_strip_and_paths(s, a, 1)
    assert s["steps"] == steps_for(fig9.QUICK_S, 10.0) == 8000 and s["sweep_factors"] == [1.0] and len(s["map"]) == 1
    assert s["real_robot"]["events"]["out of the path"]["paper_s"] == 200.0
    for net in ("plastic", "static"):
        c = s["counts"][net]
        assert sum(c[lab] for lab in fig9.OUTCOMES) == 1
        assert s["map"][0][net]["got_out"] == c["got_out"]  # the map's default cell is the same runs
        assert s["example"][net]["outcome"] == c["runs"][0]["outcome"]
    assert s["geometry"]["right_wall_face_y"] == pytest.approx(-0.23)
    assert "paper_contrast" not in s  # no verdict rule of its own: the title reads the report's judge
    assert (tmp_path / "fig9.png").stat().st_size > 50_000


def test_fig9s_title_gives_the_reports_verdicts_of_the_same_runs():
    from neurowalk.experiments.reproduce.judge_robot import fig9 as judge

    seven_of_ten = {"plastic": {"got_out": 7, "seeds": 10}, "static": {"got_out": 0, "seeds": 10}}
    s = {"counts": seven_of_ten, "quick": False}
    verdicts = [c.verdict for c in judge(s, False)]
    title = fig9.verdict_title(s)
    assert "plastic 7/10, static 0/10" in title and "NOT" not in title
    assert f"plastic goes out, {verdicts[0]}; static gets stuck, {verdicts[1]}" in title


def test_videos_are_written_on_request(tmp_path):
    res = fig8.run(Settings(seeds=1, out=tmp_path, video=True), steps=40)
    assert len(res.summary["videos"]) == 2
    for path in res.summary["videos"]:
        assert path.endswith(".mp4") and (tmp_path / path.split("/")[-1]).stat().st_size > 1000


def test_bad_seeds_and_steps_are_refused(tmp_path):
    with pytest.raises(ValueError, match="seeds"):
        fig8.run(Settings(seeds=0, out=tmp_path))
    with pytest.raises(ValueError, match="steps"):
        fig9.run(Settings(seeds=1, out=tmp_path), steps=0)


def test_a_27_hz_run_reports_times_on_the_27_hz_clock(tmp_path):
    steps = 300
    res = fig9.run(Settings(seeds=1, out=tmp_path, control_hz=27.0), steps=steps)
    s, a = res.summary, res.arrays
    assert s["control_hz"] == 27.0 and s["duration_s"] == pytest.approx(steps / 27.0)
    assert s["path_every_steps"] == 27
    assert len(a["plastic/path/0"]) == len(range(0, steps, 27)) + 1  # a point a second and the last
    t = a["plastic/example/t"]
    assert t[-1] == pytest.approx(steps / 27.0, rel=1e-3)  # 11.1 s, not the 30 s of 300 steps at 10 Hz
    assert a["plastic/snapshot_t"][-1] == pytest.approx(t[-1])
    rr = s["real_robot"]
    assert rr["control_hz"] == 27.0 and rr["same_clock"]
    for e in rr["events"].values():
        assert e["sim"]["runs"] == 1
        assert all(x is None or x <= steps / 27.0 for x in e["sim"]["times_s"])


@pytest.mark.parametrize("hz,cells", [(10.0, 9), (27.0, 1)])
def test_fig9_sweeps_its_map_at_the_simulators_rate_only(monkeypatch, tmp_path, hz, cells):
    seen = []

    def store(specs, folder, workers):
        seen.extend(specs)
        raise _StopError

    monkeypatch.setattr(fig9, "run_store_paths", store)
    with pytest.raises(_StopError):
        fig9.run(Settings(seeds=1, out=tmp_path, control_hz=hz))
    geometries = {json.dumps(s["arena_opts"], sort_keys=True) for s in seen}
    runs = {json.dumps(s, sort_keys=True) for s in seen}  # the default cell's runs are the main runs
    assert len(geometries) == cells and len(runs) == 2 * cells  # two networks, one seed per cell
