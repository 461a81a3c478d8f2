"""A figure's runs carry their configs: `neurowalk figure fig8 --quick --workers 1` makes each run's EpisodeConfig
where it enters (the figure's plan) and once more where its spec crosses into the job that runs it, no more."""

from __future__ import annotations

import collections
from pathlib import Path

import pytest

from neurowalk.cli import main
from neurowalk.sim import config


def test_a_figure_makes_each_run_s_config_at_most_twice(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    made: collections.Counter[str] = collections.Counter()
    check = config.EpisodeConfig.__post_init__

    def counted(self: config.EpisodeConfig) -> None:
        check(self)  # the checks, once per construction
        made[self.key()] += 1

    monkeypatch.setattr(config.EpisodeConfig, "__post_init__", counted)
    assert main(["figure", "fig8", "--quick", "--workers", "1", "--out", str(tmp_path / "fig8")]) == 0
    runs = {key for key, n in made.items() if n}
    assert len(runs) >= 6  # fig8's quick runs: both networks over its seeds, at 10 and 27 Hz
    assert max(made.values()) <= 2, made
