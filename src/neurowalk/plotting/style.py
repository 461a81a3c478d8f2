"""The one look of every picture neurowalk draws: sizes, colours, panel letters, legends and colour bars.

Every figure gets its matplotlib through :func:`pyplot` and is drawn by a function marked :func:`styled`, which draws
it under :data:`RC` (font sizes in points, line widths in points) and leaves matplotlib's own settings as they were:
in a notebook or an IPython shell, the user's backend (Jupyter's inline pictures) and ``rcParams`` stay theirs; the
command line, scripts and pool workers draw on the non-interactive Agg backend. The helpers below do the rest the
same way everywhere:

* :func:`network_colour`: one colour per network (plastic, static, braitenberg and the variants), the same in every
  figure; :data:`SIDE_COLOURS` for the left and right neuron or sensor (O1, I1, b1 left; O2, I2, b2 right);
  :data:`WEIGHT_STYLES` for the kind of weight (self weight b solid, inhibition c or q dashed); :data:`OUTCOME_COLOURS`
  for got out / stuck.
* :func:`letter_panels`: bold "A", "B", ... at the top-left corner of each panel, outside the data.
* :func:`legend_outside`: a legend beside or below its axes, never on the data.
* :func:`colorbar` and :func:`time_colorbar`: a labelled colour bar wherever colour stands for a value (paths
  coloured by time use :data:`TIME_CMAP`, dark blue to dark red as in the paper's Figs. 3 and 5).
"""

from __future__ import annotations

import contextlib
import functools
import sys
import textwrap
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypeVar

import matplotlib
import numpy as np
from matplotlib.font_manager import FontProperties

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.cm import ScalarMappable
    from matplotlib.colorbar import Colorbar
    from matplotlib.figure import Figure
    from matplotlib.legend import Legend
    from matplotlib.table import Table
    from matplotlib.text import Text

#: matplotlib settings of every figure: font sizes (pt), line widths (pt), white background.
RC: dict[str, Any] = {
    "font.size": 12,
    "axes.titlesize": 12,
    "axes.labelsize": 12,
    "xtick.labelsize": 10.5,
    "ytick.labelsize": 10.5,
    "legend.fontsize": 10,
    "legend.title_fontsize": 10,
    "legend.framealpha": 0.9,
    "figure.titlesize": 14,
    "lines.linewidth": 1.5,
    "lines.markersize": 6,
    "axes.linewidth": 0.9,
    "axes.titlepad": 7,
    "figure.facecolor": "white",
    "savefig.facecolor": "white",
}
#: Font sizes (pt) of what the figures write themselves: panel letters, notes and labels inside a panel.
FONT = {"letter": 17, "note": 9.5, "small": 8.5}
#: Line widths (pt): a neural trace over time, a path, a thin reference line, an emphasised line.
LINE = {"trace": 1.1, "path": 1.6, "thin": 0.8, "thick": 2.2}

#: One colour per network, the same in every figure (variants of the plastic network in purples and pinks).
NETWORK_COLOURS: dict[str, str] = {
    "plastic": "#5E3C99",
    "plastic-paper": "#5E3C99",
    "plastic, start": "#9E7CC1",
    "plastic-original": "#B2ABD2",
    "plastic-tuned": "#C51B7D",
    "plastic-params": "#DE77AE",
    "static": "#4D4D4D",
    "braitenberg": "#1B9E77",
}
#: Line style of each network where lines of several networks share an axes (equal values stay visible).
NETWORK_DASHES = {"plastic": "-", "static": "--", "braitenberg": ":"}
#: Colours of networks with none of their own (chosen by the name, so the same name always gets the same one).
EXTRA_COLOURS = ("#E6AB02", "#A6761D", "#66A61E", "#E7298A")
#: The left and right neuron, sensor or weight of the two-neuron network (O1, I1, b1 left; O2, I2, b2 right).
SIDE_COLOURS = {"left": "#1F77B4", "right": "#FF7F0E"}
#: Line style of each kind of weight: self connection b solid, inhibition (c or q = -c) dashed.
WEIGHT_STYLES = {"b": "-", "c": "--", "q": "--"}
#: The mean inhibition c = -(q1 + q2)/2 of the static and plastic networks: its line and its legend entry.
MEAN_WEIGHT = {"color": "black", "ls": "--", "lw": LINE["trace"], "label": "c = -(q1 + q2)/2"}
#: Outcomes: got out (escaped, success) and stuck (trapped, failed); a trap in Fig. 6 is blue, as in the paper.
OUTCOME_COLOURS = {"ok": "#2CA02C", "failed": "#D62728", "trap": "#1F77B4"}
#: Colour map of time along a path: dark blue (start) to dark red (end), the paper's colour code.
TIME_CMAP = "jet"
#: The label of every time colour bar.
TIME_LABEL = "time (s)"
#: The white box behind a number written on a bar or a path.
COUNT_BOX = {"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none"}
#: ``gid`` of a panel letter (tests and tools find the letters by it).
LETTER_GID = "panel-letter"


F = TypeVar("F", bound=Callable[..., Any])


def in_users_shell() -> bool:
    """This process is a user's IPython shell or Jupyter kernel (their backend is theirs to choose)."""
    ipython = sys.modules.get("IPython")
    return ipython is not None and getattr(ipython, "get_ipython", lambda: None)() is not None


def pyplot() -> Any:
    """matplotlib.pyplot: on the non-interactive Agg backend, but in a user's IPython shell or notebook
    (:func:`in_users_shell`), whose backend is left as it is. Its figures get :data:`RC` where drawn under
    :func:`styled`; the process's ``rcParams`` are not changed."""
    if not in_users_shell():
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # here, not at the top: after the backend is chosen, and only when neurowalk draws

    return plt


@contextlib.contextmanager
def look() -> Iterator[None]:
    """Within the block, matplotlib draws with :data:`RC` over the process's settings; afterwards those settings are
    as before. Only :data:`RC`'s keys are set and put back: what else changes inside the block stays (the first
    figure of a notebook loads Jupyter's inline backend, which turns on interactive mode for the next cells)."""
    before = {k: matplotlib.rcParams[k] for k in RC}
    matplotlib.rcParams.update(RC)
    try:
        yield
    finally:
        matplotlib.rcParams.update(before)


def styled(fn: F) -> F:
    """``fn`` (a function that draws a figure) runs under :func:`look`. Save its figure under :func:`look` too:
    matplotlib's tick locators read the tick label sizes from the settings as the figure is drawn."""

    @functools.wraps(fn)
    def drawn(*args: Any, **kwargs: Any) -> Any:
        with look():
            return fn(*args, **kwargs)

    return drawn  # type: ignore[return-value]


def network_colour(name: str) -> str:
    """The colour of network ``name``: its own (``plastic``, ``plastic-original``, ``static``, ...), or that of the
    longest network name inside it (``difficult (static)`` is static's, ``plastic, start b=2.4 q=3.5`` is
    ``plastic, start``'s); a name with none gets one of :data:`EXTRA_COLOURS`, the same for the same name."""
    if name in NETWORK_COLOURS:
        return NETWORK_COLOURS[name]
    if inside := [k for k in NETWORK_COLOURS if k in name]:
        return NETWORK_COLOURS[max(inside, key=len)]
    return EXTRA_COLOURS[sum(name.encode()) % len(EXTRA_COLOURS)]


def network_line(name: str) -> dict[str, Any]:
    """Line properties of network ``name`` in a plot of several networks: its colour, its dash (plastic solid,
    static dashed, braitenberg dotted; variants as their network)."""
    dash = next((d for k, d in NETWORK_DASHES.items() if k in name), "-")
    return {"color": network_colour(name), "ls": dash}


def weight_style(kind: str, side: str) -> dict[str, Any]:
    """Line properties of weight ``kind`` (``b``, ``c`` or ``q``) of the ``side`` (``left`` or ``right``) neuron."""
    return {"color": SIDE_COLOURS[side], "ls": WEIGHT_STYLES[kind], "lw": LINE["trace"]}


def letter(ax: Axes, text: str) -> Text:
    """Write panel letter ``text`` in bold at the top-left corner of ``ax``, just outside it (above the y tick
    labels, level with the title)."""
    return ax.annotate(
        text,
        xy=(0, 1),
        xycoords="axes fraction",
        xytext=(-6, 6),
        textcoords="offset points",
        ha="right",
        va="bottom",
        fontsize=FONT["letter"],
        fontweight="bold",
        gid=LETTER_GID,
    )


def letter_panels(axes: Iterable[Axes], letters: str | Sequence[str] = "ABCDEFGHIJKLMNOPQRSTUVWXYZ") -> list[Text]:
    """Letter ``axes`` in order with ``letters`` (A, B, C, ... by default; pass ``"BCD"`` to start elsewhere)."""
    axes = list(axes)
    if len(axes) > len(letters):
        raise ValueError(f"{len(axes)} panels but only {len(letters)} letters")
    return [letter(ax, t) for ax, t in zip(axes, letters, strict=False)]


def panel_letters(fig: Figure) -> list[str]:
    """The panel letters on ``fig``, in the order of its axes."""
    return [t.get_text() for ax in fig.axes for t in ax.texts if t.get_gid() == LETTER_GID]


def legend_outside(ax: Axes, *, side: str = "right", ncol: int = 1, **kwargs: Any) -> Legend:
    """A legend of ``ax`` outside its data: to the ``right`` of it (top-aligned), ``below`` it (under the x label)
    or ``above`` it (for an axes without a title). Other ``kwargs`` go to ``Axes.legend``."""
    if side == "right":
        where = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "borderaxespad": 0.0}
    elif side == "below":  # under the tick labels and the x label: their heights (pt) from the rc settings
        rc = matplotlib.rcParams
        shown = [t for t in ax.get_xticklabels() if t.get_visible()]
        lines = max([t.get_text().count("\n") + 1 for t in shown] or [0])
        ticks = rc["xtick.major.size"] + rc["xtick.major.pad"] + 1.25 * lines * _points(rc["xtick.labelsize"])
        label = rc["axes.labelpad"] + 1.25 * _points(rc["axes.labelsize"])
        under = 4.0 + ticks + label * bool(ax.get_xlabel())
        size = _points(kwargs.get("fontsize", rc["legend.fontsize"]))
        where = {"loc": "upper center", "bbox_to_anchor": (0.5, 0.0), "borderaxespad": under / size}
    elif side == "above":
        where = {"loc": "lower center", "bbox_to_anchor": (0.5, 1.0), "borderaxespad": 0.3}
    else:
        raise ValueError(f"side must be right, below or above, not {side!r}")
    return ax.legend(ncol=ncol, **{**where, **kwargs})


def _points(size: float | str) -> float:
    """A font size (points, or a name such as ``small``) in points."""
    return FontProperties(size=size).get_size_in_points()


def colorbar(mappable: ScalarMappable, ax: Axes | Sequence[Axes] | Any, label: str, **kwargs: Any) -> Colorbar:
    """A colour bar labelled ``label`` (with its unit) beside ``ax``: one axes, or several that share it (a list or
    an array of axes)."""
    many = not hasattr(ax, "get_figure")
    axes = [a for a in np.ravel(np.asarray(ax, dtype=object))] if many else ax
    first = axes[0] if many else ax
    opts = {"fraction": 0.046, "pad": 0.02, "aspect": 25, **kwargs}
    return first.get_figure().colorbar(mappable, ax=axes, label=label, **opts)


def time_colorbar(mappable: ScalarMappable, ax: Axes | Sequence[Axes] | Any, **kwargs: Any) -> Colorbar:
    """The colour bar of a path or scatter coloured by time: labelled ``time (s)``."""
    return colorbar(mappable, ax, TIME_LABEL, **kwargs)


@dataclass(frozen=True)
class BarCount:
    """A count written up a bar (:func:`bar_count`): its text, the bar's top and the ends of its error bar."""

    text: Text
    top: float
    low: float
    high: float


def bar_count(
    ax: Axes, x: float, text: str, top: float, low: float | None = None, high: float | None = None
) -> BarCount:
    """A count written up the bar at ``x`` whose top is ``top`` (in a white box); ``low`` and ``high``: the ends of its
    error bar, if it has one. :func:`place_bar_counts` puts it in place once the figure's layout is known."""
    t = ax.text(x, 0.0, text, ha="center", va="bottom", rotation=90, fontsize=FONT["small"], bbox=COUNT_BOX, zorder=4)
    low, high = top if low is None else min(low, top), top if high is None else max(high, top)
    return BarCount(t, top, low, high)


def place_bar_counts(fig: Figure, counts: Sequence[BarCount], foot: float = 0.03, gap_pt: float = 3.0) -> None:
    """Put each of ``counts`` (on axes of ``fig`` with a linear y axis) where it covers no bar but its own.

    The figure's layout is done here first (without rendering), for the sizes of the counts and the axes. A count
    stands at its bar's foot, ``foot`` above the axis (data units), where its box ends ``gap_pt`` points or more under
    the bar's top and its error bar's low end; else ``gap_pt`` points above the bar and its error bar. An axes is
    raised where a count would stick out of its top.
    """
    if not counts:
        return
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    px = fig.dpi / 72.0  # pixels per point
    tops: dict[Axes, float] = {}
    for c in counts:
        ax = c.text.axes
        lo, hi = ax.get_ylim()
        per_px = (hi - lo) / ax.get_window_extent(renderer).height  # data units of one pixel
        box = c.text.get_bbox_patch()
        shown = box.get_window_extent(renderer) if box is not None else c.text.get_window_extent(renderer)
        height, gap = shown.height * per_px, gap_pt * px * per_px
        y = foot if foot + height + gap <= c.low else c.high + gap
        c.text.set_y(y)
        tops[ax] = max(tops.get(ax, hi), y + height + gap)
    for ax, top in tops.items():
        lo, hi = ax.get_ylim()
        if top > hi:
            ax.set_ylim(lo, top)


def draw_table(
    ax: Axes,
    cells: Sequence[Sequence[str]],
    rows: Sequence[str],
    columns: Sequence[str],
    *,
    shares: Sequence[Sequence[float | None]] | None = None,
    title: str | None = None,
) -> Table:
    """A real table in ``ax`` (its frame and ticks hidden): ``cells`` (one list of strings per row) beside the
    ``rows`` labels, under the ``columns`` labels, headers in bold. ``shares`` (0-1 per cell, None for none) tint each
    cell from light red (0) to light green (1), so that a table of outcomes reads at a glance."""
    ax.axis("off")
    tints = None if shares is None else [[_tint(v) for v in row] for row in shares]
    width = 1.0 / (len(columns) + 1.4)  # the row labels' column 1.4 wide
    tab = ax.table(
        cellText=[list(r) for r in cells],
        rowLabels=list(rows),
        colLabels=[textwrap.fill(c, 18) for c in columns],
        cellColours=tints,
        colWidths=[width] * len(columns),
        cellLoc="center",
        bbox=(1.4 * width, 0.0, 1.0 - 1.4 * width, 1.0),
    )
    tab.auto_set_font_size(False)
    tab.set_fontsize(FONT["note"] + 1)
    for (r, c), cell in tab.get_celld().items():
        cell.set_edgecolor("0.7")
        if r == 0 or c == -1:
            cell.set_text_props(fontweight="bold")
    if title:
        ax.set_title(title)
    return tab


def _tint(share: float | None) -> str | tuple[float, float, float]:
    """Light red (0) through white-ish yellow to light green (1); white for None."""
    if share is None:
        return "white"
    r, g, b, _ = matplotlib.colormaps["RdYlGn"](0.15 + 0.7 * float(share))
    return (0.55 + 0.45 * r, 0.55 + 0.45 * g, 0.55 + 0.45 * b)
