"""A run's EpisodeConfig is made (and checked) where its settings enter, and again only where its spec crosses a
process boundary (a pool's worker makes it of the spec it is sent): a figure whose runs run in this process
(`--workers 1`) makes each run's config once."""

from __future__ import annotations

from pathlib import Path

import pytest

from neurowalk.cli import main
from neurowalk.sim.config import EpisodeConfig


def test_a_figure_run_in_this_process_makes_each_runs_config_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    made: list[str] = []
    checked = EpisodeConfig.__post_init__

    def counted(self: EpisodeConfig) -> None:
        checked(self)
        made.append(self.key())

    monkeypatch.setattr(EpisodeConfig, "__post_init__", counted)
    args = ["figure", "table2", "--quick", "--seeds", "2", "--workers", "1", "--out", str(tmp_path / "t")]
    assert main(args) == 0
    runs = set(made)
    assert len(runs) == 8  # the four rows' two environments each
    assert all(made.count(k) == 1 for k in runs), sorted(made.count(k) for k in runs)
