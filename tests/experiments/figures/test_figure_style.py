"""Every figure, drawn from the numbers committed under docs/results/quick (the arrays, which are not committed,
made up in the right shapes): panels lettered A, B, C, ... without gaps, every plotted axis labelled, every legend
off its panel, every panel's colour shown by a labelled colour bar or a legend, and no paragraph of text under the
plots."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator, Mapping
from pathlib import Path

import numpy as np
import pytest

from neurowalk.experiments import FIGURES, Result, Settings
from neurowalk.experiments.figures import fig2
from neurowalk.experiments.suites.random_envs_plot import CLUTTER_BINS, clutter_bins
from neurowalk.plotting.style import panel_letters

QUICK = Path(__file__).resolve().parents[3] / "docs" / "results" / "quick"
N = 6000  # rows of a made-up time series: more than the key moments and marks of the quick runs
#: The letters each figure's panels carry (fig6 and steps: small multiples and a single panel, no letters).
LETTERS = {
    "fig2": "ABCDEFG", "fig3": "ABCDEFG", "fig4": "AB", "fig5": "ABCDEFGH", "fig6": "", "fig7": "ABCD",
    "fig8": "ABCDEF", "fig10": "ABCDEF", "table1": "AB", "table2": "ABCD", "steps": "", "bodies": "ABCDE",
    "surrogate": "AB",
}  # fmt: skip


class MadeUpArrays(Mapping):
    """Arrays of a figure's npz, made up on first use from the name's last part (deterministic, seed 0)."""

    def __init__(self) -> None:
        self._made: dict[str, np.ndarray] = {}
        self._rng = np.random.default_rng(0)

    def _make(self, key: str) -> np.ndarray:
        last = key.rsplit("/", 1)[-1]
        rng = self._rng
        if last == "frames":
            return np.zeros((6, 30, 40, 3), dtype=np.uint8)
        if last == "snapshot_t":
            return np.linspace(0, 500, 6)
        if last in ("step",):
            return np.arange(N) * 10
        if last in ("t", "b_t"):
            return np.arange(1, N + 1) / 10.0
        if last in ("pose",) or re.fullmatch(r"path\d+", last) or "/path/" in key:
            return np.cumsum(rng.normal(0, 0.01, (N, 3)), axis=0)
        if last.endswith("angles"):
            return rng.normal(0, 0.3, (N, 18))
        if last.endswith("swing") or last == "foot_contact":
            return rng.random((N, 6)) > 0.5
        if last in ("latch", "coverage", "z", "bj_command", "bj_angle"):
            return np.sort(rng.random(N))
        return np.clip(rng.normal(0, 0.5, (N, 2)), -1, 1)  # inputs, outputs, weights, paths of bodies

    def __getitem__(self, key: str) -> np.ndarray:
        if key not in self._made:
            self._made[key] = self._make(key)
        return self._made[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._made)

    def __len__(self) -> int:
        return len(self._made)

    def __contains__(self, key: object) -> bool:
        return True


def _result(folder: str) -> Result:
    name = next(p.stem for p in (QUICK / folder).glob("*.json") if p.stem not in ("command", "settings"))
    if name == "fig2":  # its arrays are cheap to compute: the real ones
        return fig2.measure(Settings(quick=True), {})
    return Result(name, json.loads((QUICK / folder / f"{name}.json").read_text()), MadeUpArrays())  # type: ignore[arg-type]


def _is_plot(ax) -> bool:
    """A panel with data axes: not a colour bar, a table, a diagram or a picture."""
    return ax.axison and ax.get_label() != "<colorbar>" and not ax.images and not ax.tables


def _shown(labels) -> bool:
    return any(t.get_visible() and t.get_text() for t in labels)


FOLDERS = sorted(p.name for p in QUICK.iterdir() if (p / "command.json").is_file())  # a figure's folder, not the stores


def test_every_figure_is_here():
    names = {re.sub(r"-(27hz|1000|physics)$", "", f) for f in FOLDERS}
    assert names >= set(FIGURES)


@pytest.mark.filterwarnings("error::UserWarning")  # a layout that collapses warns
@pytest.mark.parametrize("folder", FOLDERS)
def test_a_figure_is_lettered_labelled_and_its_legends_are_off_the_data(folder):
    res = _result(folder)
    fig = FIGURES[res.name].plot(res)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    letters = "".join(panel_letters(fig))
    if res.name in LETTERS:
        assert sorted(letters) == list(LETTERS[res.name]), letters
    else:  # escape-map, latched-spin, fig9: as many as they have panels, from A without gaps
        assert letters and sorted(letters) == list("ABCDEFGHIJKLMNOP"[: len(letters)]), letters
    for ax in fig.axes:
        if not _is_plot(ax):
            continue
        where = f"{folder}: panel titled {ax.get_title()!r}"
        if _shown(ax.get_xticklabels()):
            assert ax.get_xlabel() or fig.get_supxlabel(), f"{where} has no x label"
        if _shown(ax.get_yticklabels()):
            assert ax.get_ylabel() or fig.get_supylabel(), f"{where} has no y label"
        legend = ax.get_legend()
        if legend is not None:
            assert not legend.get_window_extent(renderer).overlaps(ax.get_window_extent(renderer)), where
    texts = [*fig.texts, *(t for ax in fig.axes for t in ax.texts)]
    paragraphs = [t.get_text() for t in texts if len(t.get_text()) > 200 or t.get_text().count("\n") > 3]
    assert paragraphs == []  # the rules and counts are in the json, or a real table


@pytest.mark.parametrize("folder", ["fig5", "fig6", "latched-spin", "fig8"])
def test_paths_coloured_by_time_have_a_time_colour_bar(folder):
    res = _result(folder)
    fig = FIGURES[res.name].plot(res)
    bars = [ax.get_ylabel() for ax in fig.axes if ax.get_label() == "<colorbar>"]
    assert any(b.startswith("time (s)") for b in bars), bars


@pytest.mark.parametrize(("lo", "hi"), [(2, 20), (2, 3), (4, 4), (1, 100)])
def test_clutter_bins_are_whole_box_counts_covering_the_range_once(lo, hi):
    bins = clutter_bins(lo, hi)
    covered = [n for a, b in bins for n in range(a, b + 1)]
    assert covered == list(range(lo, hi + 1))  # every count once, in order
    assert all(isinstance(a, int) and isinstance(b, int) and a <= b for a, b in bins)
    assert len(bins) <= CLUTTER_BINS + 1


def test_table2s_failures_by_clutter_are_drawn_in_those_bins():
    res = _result("table2")
    fig = FIGURES["table2"].plot(res)
    ax = next(a for a in fig.axes if a.get_title() == "failures by clutter")
    labels = [t.get_text() for t in ax.get_xticklabels()]
    lo, hi = res.summary["boxes"]
    assert [tuple(map(int, re.match(r"(\d+)-(\d+)\n", t).groups())) for t in labels] == clutter_bins(lo, hi)
    sizes = [int(re.search(r"\n(\d+) envs", t).group(1)) for t in labels]
    assert sum(sizes) == len(res.summary["environments"])
    assert ax.get_xlabel() == "boxes in the environment"
