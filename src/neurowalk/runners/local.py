"""Run many episodes on a local process pool, with a progress bar; results in input order."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import Any

from neurowalk.sim.episode import Episode, EpisodeConfig, run_episode


def summary_only(ep: Episode) -> dict[str, Any]:
    """Keep an episode's summary (the default of :func:`run_many`)."""
    return ep.summary


def _one(args: tuple[EpisodeConfig, Callable[[Episode], Any]]) -> Any:
    cfg, keep = args
    return keep(run_episode(cfg))


def run_many(configs: Sequence[EpisodeConfig], *, workers: int = 2, progress: bool = True,
             keep: Callable[[Episode], Any] = summary_only, desc: str = "runs") -> list[Any]:  # fmt: skip
    """Run every config; return ``keep(episode)`` of each, in order.

    Args:
        configs: the runs.
        workers: processes (1 runs them here, one after the other).
        progress: show a progress bar with rate and time left.
        keep: what to keep of each episode (a module-level function, so it can be pickled).
    """
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    from tqdm import tqdm

    jobs = [(c, keep) for c in configs]
    with tqdm(total=len(jobs), unit="run", desc=desc, disable=not progress, mininterval=0.5) as bar:
        if workers == 1 or len(jobs) <= 1:
            out = []
            for job in jobs:
                out.append(_one(job))
                bar.update(1)
            return out
        with ProcessPoolExecutor(max_workers=workers) as pool:
            out = []
            for r in pool.map(_one, jobs):
                out.append(r)
                bar.update(1)
            return out
