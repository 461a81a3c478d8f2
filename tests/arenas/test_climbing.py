"""Climbing arenas: geometry, heights, refused options."""

import pytest

from neurowalk.arenas import make_arena
from neurowalk.arenas.climbing import MAX_STEP, track_regions
from neurowalk.arenas.spec import WALL_HEIGHT
from neurowalk.neural.backbone import BackboneParams


def test_single_step_has_the_requested_height_and_an_exit_on_top():
    a = make_arena("steps", height=0.08, distance=0.5)
    (slab,) = a.boxes
    assert slab.h == pytest.approx(0.08)
    assert slab.x - slab.sx / 2 == pytest.approx(0.5)
    assert a.exit_region[0] > 0.5


@pytest.mark.parametrize("step", [0.06, 0.10])
def test_track_second_platform_is_twice_the_step_and_walls_are_not_climbable(step):
    a = make_arena("climbing-track", step=step)
    heights = sorted({round(b.h, 9) for b in a.boxes})
    assert heights[:2] == [pytest.approx(step), pytest.approx(2 * step)]
    walls = [b for b in a.boxes if b.h > 2 * step + 1e-9]
    assert walls and all(b.h - 2 * step >= WALL_HEIGHT - 1e-9 for b in walls)
    assert BackboneParams().climbable < WALL_HEIGHT  # walls stay walls with climbing on
    regions = track_regions(step)
    assert regions["second platform"][4] == pytest.approx(2 * step)
    x0, x1, y0, y1 = a.exit_region
    sx0, sx1, sy0, sy1, _ = regions["second platform"]
    assert sx0 <= x0 < x1 <= sx1 and sy0 < y0 < y1 <= sy1


@pytest.mark.parametrize(
    "name,opts,word",
    [
        ("steps", {"height": 0.0}, "height"),
        ("steps", {"height": -0.05}, "height"),
        ("steps", {"height": MAX_STEP + 0.01}, "height"),
        ("steps", {"distance": 0.1}, "distance"),
        ("climbing-track", {"step": 0.5}, "step"),
        ("climbing-track", {"wall_x": 0.2}, "wall_x"),
    ],
)
def test_unbuildable_steps_are_refused(name, opts, word):
    with pytest.raises(ValueError, match=word):
        make_arena(name, **opts)
