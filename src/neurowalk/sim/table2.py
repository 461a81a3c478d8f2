"""Table 2's environments, public: the random layouts ``neurowalk figure table2`` runs each network in, as configs,
and as the arena a Gymnasium exploration environment is reset onto (``reset(options={"table2": i})``), so that a
policy and the figure are compared on the same layouts.

.. code-block:: text

    environment i of table seed s:  run seed s + i; boxes: n in [2, 20] from SeedSequence([s, i])
    its arena:                      make_arena("random", n_boxes=n, extent=9 m, size=1 m) drawn by the run's own
                                    arena generator (sim.config.seeds(config)[2]): boxes and the start pose

The figure runs environments 0..49 of table seed ``--seed`` (default 0; ``--quick``: 0..9).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from neurowalk.arenas import ArenaSpec, make_arena
from neurowalk.sim.config import EpisodeConfig, seeds

BOXES = (2, 20)  # inclusive range of the number of boxes (paper: 2 to 20)
EXTENT = 9.0  # m, side of the walled field (the original's arena is 9 x 9 m)
SIZE = 1.0  # m, side of each box (the authors' arenas use 1 x 1 m boxes)
N_ENVS = 50  # the table's environments


def table2_environments(n: int = N_ENVS, seed: int = 0) -> list[dict[str, int]]:
    """The first ``n`` environments of table seed ``seed``: ``[{"seed": run seed, "n_boxes": boxes}, ...]``."""
    if n < 0 or seed < 0:
        raise ValueError(f"n and seed must be >= 0, got n={n}, seed={seed}")
    out = []
    for i in range(n):
        rng = np.random.default_rng(np.random.SeedSequence([seed, i]))
        out.append({"seed": seed + i, "n_boxes": int(rng.integers(BOXES[0], BOXES[1] + 1))})
    return out


def table2_config(
    i: int, controller: str = "plastic", *, seed: int = 0, size: float = SIZE, **fields: Any
) -> EpisodeConfig:
    """The config of a run of ``controller`` in Table 2's environment ``i`` (of table seed ``seed``; boxes of side
    ``size`` m); ``fields``: other :class:`~neurowalk.sim.config.EpisodeConfig` fields (body, steps, variant, ...).
    E.g. ``run_episode(table2_config(3, body="surrogate", steps=20000))`` runs the figure's environment 3."""
    if not i >= 0:
        raise ValueError(f"Table 2's environment must be a number >= 0, got {i}")
    env = table2_environments(i + 1, seed)[i]
    opts = {"n_boxes": env["n_boxes"], "extent": EXTENT, "size": size}
    return EpisodeConfig(arena="random", arena_opts=opts, controller=controller, seed=env["seed"], **fields)


def table2_arena(i: int, seed: int = 0, size: float = SIZE) -> ArenaSpec:
    """The arena of Table 2's environment ``i`` as a run of it builds it: its boxes and its start pose."""
    cfg = table2_config(i, seed=seed, size=size, body="surrogate")
    return make_arena(cfg.arena, rng=seeds(cfg)[2], **cfg.arena_opts)


def table2_option(options: Mapping[str, Any] | None, copies: int | None = None) -> list[int] | None:
    """The Table 2 environments a Gymnasium reset's ``options`` ask for: ``{"table2": i}`` (a vector environment's
    copy k gets environment i + k, or ``{"table2": [i0, i1, ...]}`` one each), with ``"table2_seed"`` the table seed
    (default 0); None where they ask for none. ``copies``: the vector environment's copies (None: one environment).
    ValueError naming a bad value."""
    if not options or options.get("table2") is None:
        return None
    want = options["table2"]
    n = 1 if copies is None else copies
    if isinstance(want, Sequence) and not isinstance(want, str):
        found = [int(x) for x in want]
        if len(found) != n:
            raise ValueError(f"options['table2'] must give {n} environments, got {len(found)}")
    elif isinstance(want, int | np.integer) and not isinstance(want, bool):
        found = [int(want) + k for k in range(n)]
    else:
        raise ValueError(f"options['table2'] must be an environment number (int) or a list of them, got {want!r}")
    if min(found) < 0:
        raise ValueError(f"options['table2']: environments are numbers >= 0, got {min(found)}")
    return found


def table2_seed(options: Mapping[str, Any]) -> int:
    """The table seed of a reset's ``options`` (``"table2_seed"``, default 0)."""
    seed = options.get("table2_seed", 0)
    if not isinstance(seed, int | np.integer) or isinstance(seed, bool) or seed < 0:
        raise ValueError(f"options['table2_seed'] must be a whole number >= 0, got {seed!r}")
    return int(seed)
