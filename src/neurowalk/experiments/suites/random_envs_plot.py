"""The picture of Table 2 (:mod:`neurowalk.experiments.figures.table2`): success rates under both rules beside the
paper's, coverage per network, failures by clutter (environments binned by their number of boxes) and by class. The
rules' wording is in the json (``rule``, ``coverage_rule``, ``failure_rule``, ``held_up_rule``), not on the
picture."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import MaxNLocator, PercentFormatter

from neurowalk.experiments import Result
from neurowalk.experiments.suites.random_envs import FAILURE_CLASSES
from neurowalk.plotting.style import (
    FONT,
    BarCount,
    bar_count,
    legend_outside,
    letter_panels,
    network_colour,
    place_bar_counts,
    pyplot,
    styled,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

PAPER = {"environments": 50, "success": 49, "failure": 1}
#: Colour of each failure class (latched spin, wedged, other).
CLASS_COLOURS = ("#B2182B", "#F4A582", "0.6")
#: About this many clutter bins (whole numbers of boxes each).
CLUTTER_BINS = 5


def clutter_bins(lo: int, hi: int, n: int = CLUTTER_BINS) -> list[tuple[int, int]]:
    """``lo``..``hi`` boxes cut into about ``n`` bins of a whole number of box counts each, (first, last) inclusive:
    2..20 into (2, 5), (6, 9), (10, 13), (14, 17), (18, 20)."""
    width = max(1, math.ceil((hi - lo + 1) / n))
    return [(a, min(a + width - 1, hi)) for a in range(lo, hi + 1, width)]


def rate_bars(
    ax: Axes, x: np.ndarray, rate: np.ndarray, ci: np.ndarray, texts: list[str], width: float, **style: Any
) -> list[BarCount]:
    """Bars of the success rates ``rate`` at ``x`` (``style``: their colours, alpha, hatch), their Wilson 95%
    intervals ``ci`` (n, 2) as error bars; returns their counts ``texts``, to be put in place once drawn."""
    ax.bar(x, rate, width, edgecolor="k", lw=0.5, **style)
    yerr = np.maximum(0.0, [rate - ci[:, 0], ci[:, 1] - rate])
    ax.errorbar(x, rate, yerr=yerr, fmt="none", c="k", capsize=3)
    return [
        bar_count(ax, float(xi), t, float(r), float(lo), float(hi))
        for xi, t, r, (lo, hi) in zip(x, texts, rate, ci, strict=True)
    ]


def _rates(ax: Axes, s: dict[str, Any], names: list[str], both: bool) -> list[BarCount]:
    """Success rate of each network under both rules (hatched: the coverage rule), Wilson 95% intervals, the paper's
    49/50 and its interval as a grey band; returns the bars' counts, to be put in place (at the bar's foot, or above
    it and its interval where it is too short: :func:`~neurowalk.plotting.style.place_bar_counts`) once drawn."""
    counts = []
    x = np.arange(len(names))
    width = 0.38 if both else 0.8
    rules = [("success", "success_rate", 0.85, None)]
    if both:
        rules.append(("success_coverage", "success_coverage_rate", 0.45, "//"))
    colours = [network_colour(c) for c in names]
    for j, (ok_key, rate_key, alpha, hatch) in enumerate(rules):
        dx = (j - (len(rules) - 1) / 2) * width
        rate = np.array([s["counts"][c][rate_key] for c in names])
        ci = np.array([s["counts"][c][rate_key + "_95ci"] for c in names])
        texts = [f"{s['counts'][c][ok_key]}/{s['counts'][c]['environments']}" for c in names]
        counts += rate_bars(ax, x + dx, rate, ci, texts, width, color=colours, alpha=alpha, hatch=hatch)
    handles = [Patch(fc="0.5", alpha=0.85, ec="k", lw=0.5, label="not stuck at the end")]
    if both:
        handles.append(Patch(fc="0.5", alpha=0.45, ec="k", lw=0.5, hatch="//", label="coverage rule"))
    paper = s.get("paper", PAPER)
    if "success_rate_95ci" in paper:
        lo, hi = paper["success_rate_95ci"]
        ax.axhspan(lo, hi, color="0.88", zorder=0)
        ax.axhline(paper["success_rate"], c="0.5", lw=1, zorder=0)
        handles.append(Patch(color="0.88", label=f"paper {paper['success']}/{paper['environments']}, 95% interval"))
    agree = s.get("surrogate_agreement") or {}
    who = s.get("surrogate") or "surrogate"
    labels = [f"{c}\n{who} agrees\n{agree[c]['same_outcome']}/{agree[c]['environments']}" if c in agree else c
              for c in names]  # fmt: skip
    ax.set_xticks(x, labels, fontsize=FONT["small"] if agree else FONT["note"])
    ax.set(ylim=(0, 1.05), xlabel="network", ylabel="success rate (Wilson 95% interval)", title="success rate")
    ax.yaxis.set_major_formatter(PercentFormatter(1.0))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return counts


def _coverage(ax: Axes, s: dict[str, Any], names: list[str]) -> None:
    """Coverage of every environment per network (box: quartiles and 1.5 IQR whiskers; dots: the environments) and
    the coverage rule's threshold."""
    x = np.arange(len(names))
    cov = [[np.nan if r[c]["coverage"] is None else r[c]["coverage"] for r in s["environments"]] for c in names]
    ax.boxplot([[v for v in c if np.isfinite(v)] for c in cov], positions=x, widths=0.5, showfliers=False,
               medianprops={"color": "k", "lw": 1.5})  # fmt: skip
    for i, v in enumerate(cov):
        jitter = np.linspace(-0.15, 0.15, len(v)) if len(v) > 1 else np.zeros(len(v))
        ax.plot(i + jitter, v, ".", c=network_colour(names[i]), ms=4, alpha=0.6)
    if "coverage_threshold" in s:
        ax.axhline(s["coverage_threshold"], c="k", ls="--", lw=1, label=f"threshold {s['coverage_threshold']:.1%}")
        legend_outside(ax)
    ax.set_xticks(x, names, fontsize=FONT["note"])
    ax.yaxis.set_major_formatter(PercentFormatter(1.0))
    cell = s.get("coverage_cell_m", 0.25)
    ax.set(xlabel="network", ylabel=f"coverage (share of free {cell:g} m cells)", title="coverage per environment")


def _by_clutter(ax: Axes, s: dict[str, Any], names: list[str], both: bool) -> None:
    """Share of the environments of each clutter bin (whole numbers of boxes) that a network failed: bars for the
    not-stuck rule, black ticks for the coverage rule."""
    bins = clutter_bins(int(s["boxes"][0]), int(s["boxes"][1]))
    envs = s["environments"]
    members = [[r for r in envs if lo <= r["n_boxes"] <= hi] for lo, hi in bins]
    x = np.arange(len(bins))
    width = 0.8 / len(names)
    for i, c in enumerate(names):
        dx = (i - (len(names) - 1) / 2) * width
        share = [sum(not r[c]["success"] for r in m) / len(m) if m else np.nan for m in members]
        ax.bar(x + dx, share, width * 0.95, color=network_colour(c), label=c)
        if both:
            cover = [sum(not r[c]["success_coverage"] for r in m) / len(m) if m else np.nan for m in members]
            ax.plot(x + dx, cover, "_", color="k", ms=12, mew=2)
    labels = [
        (f"{lo}-{hi}" if hi > lo else f"{lo}") + f"\n{len(m)} envs" for (lo, hi), m in zip(bins, members, strict=True)
    ]
    ax.set_xticks(x, labels, fontsize=FONT["note"])
    ax.set(ylim=(0, 1.05), xlabel="boxes in the environment", ylabel="failed (share of the bin's environments)")
    ax.yaxis.set_major_formatter(PercentFormatter(1.0))
    ax.set_title("failures by clutter")
    handles, _ = ax.get_legend_handles_labels()
    if both:
        handles.append(Line2D([], [], ls="none", marker="_", color="k", ms=12, mew=2, label="coverage rule"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, title="bars: not stuck")


def _by_class(ax: Axes, s: dict[str, Any], names: list[str]) -> None:
    """Failures (not-stuck rule) of each network stacked by class; under each network, how many successes were held
    up for 300 s or more."""
    x = np.arange(len(names))
    bottom = np.zeros(len(names))
    for j, cls in enumerate(FAILURE_CLASSES):
        v = np.array([s["counts"][c].get("failure_classes", {}).get(cls, 0) for c in names])
        ax.bar(x, v, 0.6, bottom=bottom, color=CLASS_COLOURS[j], label=cls)
        bottom += v
    held = [s["counts"][c].get("held_up_300s_success") for c in names]
    ax.set_xticks(x, [c if h is None else f"{c}\nheld up: {h}" for c, h in zip(names, held, strict=True)])
    ax.tick_params(axis="x", labelsize=FONT["note"])
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set(ylim=(0, max(1.0, float(bottom.max())) * 1.1), xlabel="network", ylabel="failures (not-stuck rule)")
    ax.set_title("failures by class (held up: successes held up >= 300 s)")
    legend_outside(ax)


@styled
def plot(res: Result) -> Figure:
    """A: success rates under both rules with 95% intervals beside the paper's; B: coverage per network with the
    rule's threshold; C: failures by clutter; D: failures by class."""
    plt = pyplot()
    s = res.summary
    names = list(s["counts"])
    both = all("success_coverage" in s["counts"][c] for c in names)  # a json of the code before the coverage rule
    fig, ax = plt.subplots(2, 2, figsize=(16, 11), layout="constrained")
    counts = _rates(ax[0, 0], s, names, both)
    _coverage(ax[0, 1], s, names)
    _by_clutter(ax[1, 0], s, names, both)
    _by_class(ax[1, 1], s, names)
    letter_panels(ax.flat)
    on = " with climbing modules" if s.get("climbing") else ""
    hz = s.get("control_hz", 10.0)
    fig.suptitle(
        f"Table 2 on {s['body']}{on}: {s['counts'][names[0]]['environments']} random environments, "
        f"{s.get('box_size_m', 0.6):g} m boxes, {s['steps'] / hz:g} s at {hz:g} Hz"
    )
    place_bar_counts(fig, counts)
    return fig
