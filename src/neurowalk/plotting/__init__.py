"""Pictures: the shared look of every figure (:mod:`.style`) and pictures of runs (:mod:`.runs`)."""

from neurowalk.plotting.runs import draw_arena, plot_run, run_title
from neurowalk.plotting.style import look, pyplot, styled

__all__ = ["draw_arena", "look", "plot_run", "pyplot", "run_title", "styled"]
