"""Fig. 8 (narrow passage) and Fig. 9 (complex path): outcome rules, resumable store, smoke runs of both figures."""

import json

import numpy as np
import pytest

from fake_runs import kept_of, plan, summary_of
from neurowalk.arenas import make_arena
from neurowalk.arenas.generated import MOUTH, OPENING
from neurowalk.cli import main
from neurowalk.experiments import FIGURES, Settings
from neurowalk.experiments.figures import fig8, fig9
from neurowalk.experiments.study import compute
from neurowalk.experiments.study_runs import Kept, run_store
from neurowalk.experiments.suites.real_robot import (
    PATH,
    camera_view,
    config,
    path_every,
    sampled,
    snapshot_rows,
    video_every,
)
from neurowalk.sim.run_summary import RunSummary


def test_both_figures_are_registered_with_the_options_the_cli_passes():
    for name in ("fig8", "fig9"):
        assert {"seeds", "video", "variant", "params", "control_hz", "workers"} <= set(FIGURES[name].takes)


def test_the_runs_carry_the_network_variant_and_overrides():
    cfg = plan("fig8", Settings(variant="original", params={"a": 4.0}, seeds=1))[0].config
    assert cfg.controller == "plastic" and cfg.seed == 0 and cfg.variant == "original" and cfg.params == {"a": 4.0}
    plain = [p.config for p in plan("fig8", Settings(seeds=1))]
    at27 = [p.config for p in plan("fig8", Settings(control_hz=27, seeds=1))]
    assert all(c.params is None and c.variant == "paper" and c.control_hz == 10.0 for c in plain)
    assert all(c.control_hz == 27 for c in at27)


@pytest.mark.parametrize(("fig", "quick", "steps"), [(fig8, True, 5000), (fig8, False, 5000), (fig9, True, 8000)])
@pytest.mark.parametrize("hz", [10.0, 27.0])
def test_runs_last_as_many_control_steps_at_either_rate_and_stop_once_out(fig, quick, steps, hz):
    seen = [p.config for p in plan(fig.NAME, Settings(quick=quick, seeds=2, control_hz=hz))]
    assert seen and all(c.control_hz == hz and c.until == "escaped" for c in seen)
    assert {c.steps for c in seen} == {steps}  # the networks' time: as many updates at 27 Hz as at 10 Hz


def test_each_run_keeps_its_path_and_the_first_seed_of_each_network_its_example():
    runs = plan("fig9", Settings(seeds=2))
    full = [(p.label, p.config.seed) for p in runs if [t.name for t in p.terms] == ["path", "example"]]
    assert full == [(("plastic", (1.0, 1.0)), 0), (("static", (1.0, 1.0)), 0)]
    assert all(PATH in p.terms for p in runs)


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


def test_a_path_holds_a_point_a_second_and_the_last(tmp_path):
    runs = [(config("narrow-passage", {}, net, 0, 30), (PATH,)) for net in ("plastic", "static")]
    assert all(len(r["kept"]["path"]["path"]) == 4 for r in run_store(runs, tmp_path, 1))  # rows 0, 10, 20, 29


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
        # the example drawn is the first seed's stored run: its pose, sampled as a path is, is that seed's path
        example_path = np.round(sampled(a[f"{net}/example/pose"][:, :2], path_every(s["control_hz"])), 3)
        np.testing.assert_array_equal(a[f"{net}/path/0"], example_path)
    assert s["rule"] and s["geometry"]["boxes"]
    assert {p["body"] for p in s["physics_settings"]} == {s["body"]}  # the body its runs stepped


def test_fig8_quick_from_the_command_line_then_replot(tmp_path):
    assert main(["figure", "fig8", "--quick", "--seeds", "1", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "fig8.json").read_text())
    with np.load(tmp_path / "fig8.npz") as z:
        a = {k: z[k] for k in z.files}
    _check_strip_and_paths(s, a, 1)
    assert s["steps"] == fig8.STEPS == 5000 and s["seeds"] == 1
    assert s["control_hz"] == 10.0 and s["duration_s"] == 500.0
    rr = s["real_robot"]
    seen_to_out = rr["events"]["obstacle seen to escaped"]
    assert seen_to_out["paper_s"] == 40.0 and not rr["same_clock"] and rr["note"]  # 0:10 to 0:50
    run = s["counts"]["plastic"]["runs"][0]
    if run["escaped"]:
        assert 0 < run["seen_time_s"] < run["exit_time_s"]  # it met the funnel's walls after its start
        assert seen_to_out["sim"]["times_s"] == [pytest.approx(run["exit_time_s"] - run["seen_time_s"])]
    for net in ("plastic", "static"):
        c = s["counts"][net]
        assert c["escaped"] == sum(r["escaped"] for r in c["runs"]) and s["escaped"][net] == f"{c['escaped']}/1"
        assert a[f"{net}/path/0"][0] == pytest.approx([0.0, 0.0], abs=0.02)
    png, numbers = tmp_path / "fig8.png", (tmp_path / "fig8.json").read_text()
    png.write_bytes(b"not the picture")
    assert main(["figure", "fig8", "--replot", "--out", str(tmp_path)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 50_000  # drawn again
    assert (tmp_path / "fig8.json").read_text() == numbers  # from the numbers written, nothing run again


def test_fig9_quick_from_the_command_line(tmp_path):
    assert main(["figure", "fig9", "--quick", "--seeds", "1", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "fig9.json").read_text())
    with np.load(tmp_path / "fig9.npz") as z:
        a = {k: z[k] for k in z.files}
    _check_strip_and_paths(s, a, 1)
    assert s["steps"] == fig9.STEPS == 8000 and s["sweep_factors"] == [1.0] and len(s["map"]) == 1
    events = s["real_robot"]["events"]
    assert events["obstacle seen to the end approached"]["paper_s"] == 48.0  # 0:20 to 1:08
    assert events["the end approached to out of the path"]["paper_s"] == 132.0  # 1:08 to 3:20
    for net in ("plastic", "static"):
        c = s["counts"][net]
        assert sum(c[lab] for lab in fig9.OUTCOMES) == 1
        assert s["example"][net]["outcome"] == c["runs"][0]["outcome"]
    assert s["geometry"]["right_wall_face_y"] == pytest.approx(-0.23)
    assert "paper_contrast" not in s  # no verdict rule of its own: the title reads the report's judge
    assert (tmp_path / "fig9.png").stat().st_size > 50_000


def test_fig9s_title_gives_the_reports_verdicts_of_the_same_runs():
    judge = fig9.claims

    seven_of_ten = {"plastic": {"got_out": 7, "seeds": 10}, "static": {"got_out": 0, "seeds": 10}}
    s = {"counts": seven_of_ten, "quick": False}
    verdicts = [c.verdict for c in judge(s, False)]
    title = fig9.verdict_title(s)
    assert "plastic 7/10, static 0/10" in title and "NOT" not in title
    assert f"plastic goes out, {verdicts[0]}; static gets stuck over 5,400 control steps, {verdicts[1]}" in title


def test_the_static_robot_is_judged_over_the_papers_window():
    """Stuck: still in the path after the 5,400 control steps (3:20 at 27 Hz) the real plastic robot took to get
    out, at any rate; the share by window is in the rule."""
    runs = [{"out_time_s": t} for t in (264.0, 339.0, None)]  # 7,128 and 9,153 steps at 27 Hz, and never
    s = {"counts": {"plastic": {"got_out": 3, "seeds": 3}, "static": {"got_out": 2, "seeds": 3, "runs": runs}},
         "control_hz": 27.0, "duration_s": 800.0}  # fmt: skip
    stuck = fig9.claims(s, False)[1]
    assert stuck.measured == "3/3" and stuck.verdict == "reproduced"  # none out within 5,400 steps
    assert "7,000 steps 3/3" in stuck.rule and "8,000 steps 2/3" in stuck.rule  # where it flips
    s10 = {**s, "control_hz": 10.0}  # the same seconds at 10 Hz are fewer steps: 2,640 and 3,390, both within it
    assert fig9.claims(s10, False)[1].measured == "1/3"


def test_videos_are_written_on_request(monkeypatch, tmp_path):
    monkeypatch.setattr(fig8, "STEPS", 40)
    res = compute(FIGURES["fig8"], Settings(seeds=1, out=tmp_path, video=True))
    assert len(res.summary["videos"]) == 2
    for path in res.summary["videos"]:
        assert path.endswith(".mp4") and (tmp_path / path.split("/")[-1]).stat().st_size > 1000


def test_bad_seeds_are_refused(tmp_path):
    with pytest.raises(ValueError, match="seeds"):
        compute(FIGURES["fig8"], Settings(seeds=0, out=tmp_path))


def test_a_27_hz_run_reports_times_on_the_27_hz_clock(monkeypatch, tmp_path):
    steps = 300
    monkeypatch.setattr(fig9, "STEPS", steps)
    res = compute(FIGURES["fig9"], Settings(seeds=1, out=tmp_path, control_hz=27.0))
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
def test_fig9_sweeps_its_map_at_the_simulators_rate_only(hz, cells):
    seen = [p.config for p in plan("fig9", Settings(seeds=1, control_hz=hz))]
    geometries = {json.dumps(c.arena_opts, sort_keys=True) for c in seen}
    runs = {c.key() for c in seen}  # the default cell's runs are the main runs
    assert len(geometries) == cells and len(runs) == 2 * cells  # two networks, one seed per cell


def test_fig9s_map_counts_each_cells_own_runs_and_its_default_cell_the_main_ones():
    """Stand-in runs: the plastic network's path ends 0.75 m left of the start, out of the path where it is narrower
    than by default (left edge at 0.684 m) or as wide (0.73 m), not where it is wider (0.776 m); the static network
    walks out of the default geometry only. Each cell of the map counts its own runs, judged in its own geometry."""
    edge = np.array([[0.0, 0.0], [1.0, 0.1], [2.0, 0.75]])
    stuck, out = np.zeros((3, 2)), np.array([[0.0, 0.0], [1.0, 0.1], [2.0, 2.0]])
    s = Settings(seeds=1)
    grouped: dict = {}
    for p in plan("fig9", s):
        (net, cell), cfg = p.label, p.config
        path = out if net == "static" and cell == (1.0, 1.0) else edge if net == "plastic" else stuck
        kept = {**kept_of(cfg, [t.name for t in p.terms]), "path": {"path": path, "seen_step": None}}
        grouped.setdefault((net, cell), []).append(Kept(RunSummary.from_dict(summary_of(cfg)), kept, p))
    res = fig9.measure(s, grouped)
    cells = res.summary["map"]
    assert len(cells) == 9
    for c in cells:
        assert c["plastic"]["got_out"] == (c["width_factor"] <= 1.0) and c["plastic"]["seeds"] == 1
        assert c["static"]["got_out"] == (c["width_factor"] == c["spacing_factor"] == 1.0)
    (default,) = [c for c in cells if c["width_factor"] == c["spacing_factor"] == 1.0]
    counts = res.summary["counts"]
    assert {net: default[net]["got_out"] for net in fig9.NETWORKS} == {"plastic": 1, "static": 1}
    assert {net: counts[net]["got_out"] for net in fig9.NETWORKS} == {"plastic": 1, "static": 1}
