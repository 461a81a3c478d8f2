"""plotting.style: panel letters at the top-left corner, legends off the data, labelled colour bars, one colour per
network, real tables; every check on a drawn figure (window extents in pixels)."""

from __future__ import annotations

import subprocess
import sys

import matplotlib
import numpy as np
import pytest

from neurowalk.plotting import style


@pytest.fixture
def plt():
    with style.look():
        yield style.pyplot()


def _extent(fig, artist):
    fig.canvas.draw()
    return artist.get_window_extent(fig.canvas.get_renderer())


def test_a_styled_figure_has_the_talk_sizes_and_the_process_keeps_its_own():
    plt = style.pyplot()
    assert matplotlib.get_backend().lower() == "agg"  # not a user's shell: the non-interactive backend
    before = dict(matplotlib.rcParams)

    @style.styled
    def draw():
        fig, ax = plt.subplots()
        ax.set(title="t", xlabel="x")
        ax.plot([0, 1], [0, 1])
        return fig, ax

    fig, ax = draw()
    fig.canvas.draw()
    assert ax.title.get_fontsize() == style.RC["axes.titlesize"] >= 11
    assert ax.xaxis.label.get_fontsize() == style.RC["axes.labelsize"]
    assert ax.xaxis.get_major_ticks()[0].label1.get_fontsize() == style.RC["xtick.labelsize"]
    assert ax.lines[0].get_linewidth() == style.RC["lines.linewidth"]
    assert dict(matplotlib.rcParams) == before  # nothing of the style stays behind
    plt.close(fig)


SHELL = """
import matplotlib
from IPython.core.interactiveshell import InteractiveShell
InteractiveShell.instance()  # a running IPython shell (get_ipython() finds it), as in a notebook's kernel
matplotlib.use("svg")  # the user's backend (Jupyter's inline one, in a notebook)
matplotlib.rcParams["font.size"] = 7.0  # the user's own default
from neurowalk import EpisodeConfig, plot_run, run_episode
fig = plot_run(run_episode(EpisodeConfig(arena="open", body="surrogate", steps=30)))
sizes = sorted({t.get_fontsize() for ax in fig.axes for t in (ax.title, ax.xaxis.label) if t.get_text()})
print(matplotlib.get_backend(), matplotlib.rcParams["font.size"], sizes)
"""


def test_in_a_users_shell_the_backend_and_defaults_stay_theirs():
    pytest.importorskip("IPython")  # the test extra's (Jupyter's)
    done = subprocess.run([sys.executable, "-c", SHELL], capture_output=True, text=True, check=True)
    out = done.stdout.split(maxsplit=2)
    assert out[0] == "svg" and float(out[1]) == 7.0  # their backend, their default
    assert str(float(style.RC["axes.titlesize"])) in out[2]  # neurowalk's figure has neurowalk's sizes


def test_letters_sit_bold_at_the_top_left_corner_outside_each_panel(plt):
    fig, axes = plt.subplots(2, 2, layout="constrained")
    for ax in axes.flat:
        ax.plot([0, 1], [0, 1])
        ax.set(title="a title", ylabel="y (m)")
    texts = style.letter_panels(axes.flat)
    assert style.panel_letters(fig) == ["A", "B", "C", "D"]
    for ax, t in zip(axes.flat, texts, strict=True):
        box, frame = _extent(fig, t), _extent(fig, ax)
        assert t.get_fontweight() == "bold" and t.get_fontsize() == style.FONT["letter"]
        assert box.x1 <= frame.x0 + 1  # left of the panel's left edge
        assert box.y0 >= frame.y1 - 1  # above its top edge
        assert box.x0 >= fig.bbox.x0 and box.y1 <= fig.bbox.y1  # and inside the picture
        title = _extent(fig, ax.title)
        assert not box.overlaps(title)


def test_letters_can_start_elsewhere_and_refuse_too_many_panels(plt):
    fig, axes = plt.subplots(1, 3)
    style.letter_panels(axes, "BCD")
    assert style.panel_letters(fig) == ["B", "C", "D"]
    with pytest.raises(ValueError, match="3 panels"):
        style.letter_panels(axes, "AB")


@pytest.mark.parametrize("side", ["right", "below", "above"])
def test_a_legend_outside_never_covers_the_axes(plt, side):
    fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
    t = np.linspace(0, 10, 200)
    for k in range(3):
        ax.plot(t, np.sin(t + k), label=f"trace {k}")
    ax.set_xticks([0, 5, 10], ["start\nof run", "middle", "end\nof run"])  # two-line tick labels
    ax.set(xlabel="time (s)", ylabel="output O")
    legend = style.legend_outside(ax, side=side, ncol=3 if side != "right" else 1)
    box, frame = _extent(fig, legend), _extent(fig, ax)
    assert not box.overlaps(frame)
    if side == "below":  # under the x label and the tick labels too
        assert box.y1 <= _extent(fig, ax.xaxis.label).y0 + 1
        assert all(box.y1 <= _extent(fig, t).y0 + 1 for t in ax.get_xticklabels() if t.get_text())


def test_legend_outside_refuses_an_unknown_side(plt):
    _, ax = plt.subplots()
    ax.plot([0, 1], label="x")
    with pytest.raises(ValueError, match="right, below or above"):
        style.legend_outside(ax, side="inside")


def test_colour_bars_are_labelled_beside_one_axes_or_several(plt):
    fig, axes = plt.subplots(2, 2, layout="constrained")
    im = axes[0, 0].imshow(np.arange(4.0).reshape(2, 2))
    one = style.colorbar(im, axes[0, 0], "hysteresis width (input I)")
    shared = style.time_colorbar(im, axes)  # an array of axes
    listed = style.time_colorbar(im, [axes[1, 0], axes[1, 1]])
    assert one.ax.get_ylabel() == "hysteresis width (input I)"
    assert shared.ax.get_ylabel() == listed.ax.get_ylabel() == "time (s)"
    assert sum(ax.get_label() == "<colorbar>" for ax in fig.axes) == 3


def test_each_network_has_one_colour_everywhere():
    plastic, static, braitenberg = (style.network_colour(n) for n in ("plastic", "static", "braitenberg"))
    assert len({plastic, static, braitenberg}) == 3
    assert style.network_colour("plastic-paper") == plastic == style.network_colour("difficult (plastic)")
    assert style.network_colour("difficult (static)") == static
    assert style.network_colour("plastic-original") not in (plastic, static, braitenberg)
    assert style.network_colour("plastic, start b=2.4 q=3.5") == style.NETWORK_COLOURS["plastic, start"]
    assert style.network_colour("evolved") == style.network_colour("evolved") in style.EXTRA_COLOURS
    assert style.network_line("difficult (braitenberg)") == {"color": braitenberg, "ls": ":"}
    assert style.network_line("static")["ls"] != style.network_line("plastic")["ls"]


def test_weights_are_coloured_by_side_and_dashed_by_kind():
    b1, c2 = style.weight_style("b", "left"), style.weight_style("c", "right")
    assert b1["color"] == style.SIDE_COLOURS["left"] and c2["color"] == style.SIDE_COLOURS["right"]
    assert b1["ls"] == "-" and c2["ls"] == "--" == style.weight_style("q", "left")["ls"]


def test_a_table_is_a_real_table_tinted_by_share(plt):
    _, ax = plt.subplots()
    tab = style.draw_table(ax, [["10/10", "0/10"]], ["narrow passage"], ["plastic", "static"], shares=[[1.0, 0.0]])
    cells = tab.get_celld()
    assert cells[1, 0].get_text().get_text() == "10/10" and cells[0, 1].get_text().get_text() == "static"
    assert cells[1, -1].get_text().get_text() == "narrow passage"
    assert cells[0, 0].get_text().get_fontweight() == "bold"
    r, g, _, _ = cells[1, 0].get_facecolor()
    assert g > r  # all escaped: green
    r, g, _, _ = cells[1, 1].get_facecolor()
    assert r > g  # none escaped: red
    assert not ax.axison


@pytest.mark.parametrize("dpi", [72, 120])
def test_bar_counts_never_cover_a_bar_or_its_interval(plt, dpi):
    fig, ax = plt.subplots(figsize=(6, 4), dpi=dpi, layout="constrained")
    rates, lows, highs = [0.9, 0.02, 0.14, 0.5], [0.8, 0.0, 0.07, 0.45], [0.95, 0.1, 0.26, 0.55]
    bars = ax.bar(range(4), rates, 0.6)
    ax.errorbar(range(4), rates, yerr=[np.subtract(rates, lows), np.subtract(highs, rates)], fmt="none", c="k")
    ax.set_ylim(0, 1.05)
    counts = [
        style.bar_count(ax, i, f"{i}1/1000", r, lo, hi)
        for i, (r, lo, hi) in enumerate(zip(rates, lows, highs, strict=True))
    ]
    style.place_bar_counts(fig, counts)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for i, c in enumerate(counts):
        box = c.text.get_bbox_patch().get_window_extent(renderer)
        whisker_low, whisker_high = (ax.transData.transform((i, v))[1] for v in (lows[i], highs[i]))
        for j, bar in enumerate(bars):
            if j != i:  # another bar: never touched
                assert not box.overlaps(bar.get_window_extent(renderer)), (i, j)
        inside = box.y1 <= bars[i].get_window_extent(renderer).y1
        assert inside == (i in (0, 3))  # the tall bars hold their counts; the short ones' go above
        assert box.y1 < whisker_low if inside else box.y0 > whisker_high  # clear of the interval either way
        assert ax.get_window_extent(renderer).contains(box.x0, box.y1)  # and inside the axes


def test_a_count_that_would_stick_out_raises_the_axes(plt):
    fig, ax = plt.subplots(figsize=(4, 3), layout="constrained")
    ax.bar([0], [0.01])
    ax.set_ylim(0, 1.05)
    count = style.bar_count(ax, 0, "1/1000", 0.01, 0.0, 1.0)  # an interval up to the top: no room above it
    style.place_bar_counts(fig, [count])
    assert ax.get_ylim()[1] > 1.05 and count.text.get_position()[1] > 1.0
