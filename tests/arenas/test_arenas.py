"""Contract tests over every registered arena: builds, compiles, steps finitely, deterministic."""

import numpy as np
import pytest

from neurowalk.arenas import ARENAS, arena_options, make_arena
from neurowalk.sim.episode import EpisodeConfig, run_episode


@pytest.mark.parametrize("name", sorted(ARENAS))
def test_every_arena_compiles_runs_finite_and_deterministic(name):
    a = run_episode(EpisodeConfig(arena=name, controller="plastic", steps=60, seed=1))
    b = run_episode(EpisodeConfig(arena=name, controller="plastic", steps=60, seed=1))
    assert np.all(np.isfinite(a.trajectory.qpos))
    np.testing.assert_array_equal(a.trajectory.qpos, b.trajectory.qpos)
    assert a.summary["arena_opts"] == arena_options(name)


def test_bad_options_are_named():
    with pytest.raises(ValueError, match="no option 'gap'"):
        make_arena("box", gap=1)
    with pytest.raises(ValueError, match="distance"):
        make_arena("box", distance=0.1)
    with pytest.raises(ValueError, match="not a float"):
        make_arena("box", width="wide")
    with pytest.raises(ValueError, match="unknown arena"):
        make_arena("maze")


def test_box_geometry():
    spec = make_arena("box", distance=1.0, width=0.8)
    (box,) = spec.boxes
    assert box.x - box.sx / 2 == pytest.approx(1.0)
    assert box.contains(np.array([[1.1, 0.39]]))[0] and not box.contains(np.array([[1.1, 0.41]]))[0]


def test_random_layout_comes_from_the_generator_and_spares_the_start():
    a = make_arena("random", rng=np.random.default_rng(1), n_boxes=20)
    b = make_arena("random", rng=np.random.default_rng(1), n_boxes=20)
    c = make_arena("random", rng=np.random.default_rng(2), n_boxes=20)
    assert a == b and a != c
    assert len(a.boxes) == 4 + 20
    assert not any(box.contains(np.zeros((1, 2)), margin=0.25)[0] for box in a.boxes)


@pytest.mark.parametrize(
    "name,opts,word",
    [
        ("narrow-passage", {"gap": 0}, "gap"),
        ("narrow-passage", {"gap": -0.1}, "gap"),
        ("narrow-passage", {"gap": 2.0}, "gap"),
        ("simple-deadlock", {"width": 0.2}, "width"),
        ("narrow-passage", {"funnel": 40}, "funnel"),
        ("corner", {"angle": 5}, "angle"),
        ("random", {"n_boxes": 500}, "n_boxes"),
        ("box", {"distance": 0.2}, "distance"),
    ],
)
def test_geometry_that_cannot_be_built_is_refused(name, opts, word):
    with pytest.raises(ValueError, match=word):
        make_arena(name, **opts)


def test_dead_ends_have_exit_regions_behind_the_start():
    for name in ("simple-deadlock", "narrow-passage", "corner"):
        spec = make_arena(name)
        _, x1, _, _ = spec.exit_region
        assert x1 < spec.start[0] - 0.5


def _covered(spec, pts):
    """Cells covered by some box, box by box through Box.contains (free_cells' definition)."""
    covered = np.zeros(len(pts), dtype=bool)
    for b in spec.boxes:
        covered |= b.contains(pts)
    return covered


@pytest.mark.parametrize("name", sorted(ARENAS))
def test_free_cells_and_one_point_contains_give_box_contains_answers(name):
    spec = make_arena(name, rng=np.random.default_rng(3))
    if spec.bounds is not None:
        for cell in (0.1, 0.25, 0.7):
            x0, x1, y0, y1 = spec.bounds
            xs, ys = np.arange(x0 + cell / 2, x1, cell), np.arange(y0 + cell / 2, y1, cell)
            pts = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
            np.testing.assert_array_equal(spec.free_cells(cell), pts[~_covered(spec, pts)])
    rng = np.random.default_rng(4)
    for b in spec.boxes:
        # points near the edges (some exactly on them: a box of side 1 at a whole-metre centre) and far
        pts = np.vstack([rng.uniform(-1, 1, (200, 2)) * [b.sx, b.sy] + [b.x, b.y], [[b.x + b.sx / 2, b.y]]])
        many = b.contains(pts, margin=0.05)
        assert [b.contains(p, margin=0.05)[0] for p in pts] == many.tolist()
        assert [b.contains(p[None, :])[0] for p in pts] == b.contains(pts).tolist()
