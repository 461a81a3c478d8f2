"""A run shown in the browser while it runs (``neurowalk run ... --web``), on the replay's page.

:class:`LiveRun` is the run's sink beside its own (the part files): it copies each chunk of rows into a growing
:class:`~neurowalk.plotting.replay.Replay` (the robot's poses by forward kinematics, as a replay computes them) and
hands the rows on. :class:`LivePage` is the replay page over it: while "follow the run" is ticked it shows the newest
step, a few times a second, and redraws the traces over the steps so far every second. The page samples: the run
never waits for it, and a slow browser sees fewer frames. When the run ends the page stays, a replay of the whole
run, until Ctrl-C.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable
from typing import Any

import numpy as np

from neurowalk.plotting.replay import MAX_FRAMES, Replay, Scenery
from neurowalk.plotting.web import ReplayPage
from neurowalk.sim.config import EpisodeConfig
from neurowalk.sim.trajectory import Trajectory

#: How often the page shows the newest step (Hz) and redraws the traces (s).
FOLLOW_HZ, TRACES_EVERY_S = 5.0, 1.0
#: Rows per chunk of a run shown live (its part files are this size; a run's default is 10,000).
LIVE_CHUNK = 100


class LiveRun:
    """The rows of a running episode, kept as a growing replay; called as a sink: ``live(rows, start)``.

    Args:
        cfg: the run's config (its world).
        then: the run's own sink, called with the same rows after they are kept (None: none).
    """

    chunk = LIVE_CHUNK  # rows per sink call the run should use

    def __init__(self, cfg: EpisodeConfig, then: Callable[[Trajectory, int], Any] | None = None) -> None:
        self.scenery = Scenery(cfg)
        self.then = then
        steps, parts = cfg.steps, len(self.scenery.parts)
        self.stride = max(1, math.ceil(steps / MAX_FRAMES))
        frames = np.arange(0, steps, self.stride)
        quat = np.zeros((len(frames), parts, 4))
        quat[..., 0] = 1.0
        title = f"{cfg.arena}, {cfg.body}, {cfg.controller}, {steps} steps (live)"
        weights = 0.0 if cfg.controller == "plastic" else np.nan  # the page draws the weights of a learning network
        self.replay = Replay(
            title, float(cfg.control_hz), np.zeros(steps), frames, self.scenery.fixed, self.scenery.parts,
            np.zeros((len(frames), parts, 3)), quat, np.zeros((steps, 3)), np.zeros((len(frames), 2, 3)),
            np.zeros((len(frames), 2, 3)), np.zeros((steps, 2)), np.zeros((steps, 2)), np.full((steps, 2), weights),
            np.full((steps, 2), weights),
        )  # fmt: skip
        self.done = 0  # rows kept so far

    def __call__(self, rows: Trajectory, start: int) -> None:
        r, stop = self.replay, start + len(rows.t)
        r.t[start:stop], r.inputs[start:stop], r.outputs[start:stop] = rows.t, rows.inputs, rows.outputs
        r.b[start:stop], r.q[start:stop] = rows.b, rows.q
        r.path[start:stop] = self.scenery.path(rows)
        first, last = math.ceil(start / self.stride), math.ceil(stop / self.stride)  # frames in [start, stop)
        if last > first:
            picked = r.frames[first:last] - start
            chunk = rows.map(lambda v: v[picked])
            r.pos[first:last], r.quat[first:last], r.ray_from[first:last], r.ray_to[first:last] = self.scenery.poses(
                chunk
            )
        self.done = stop
        if self.then is not None:
            self.then(rows, start)

    def qpos_rows(self, rows: Any) -> Any:
        """The run's own sink's ``qpos_rows`` (a streamed run replays its wedged periods' contacts with it)."""
        return self.then.qpos_rows(rows)  # type: ignore[union-attr]


class LivePage(ReplayPage):
    """The replay page over a :class:`LiveRun`: it follows the run while "follow the run" is ticked."""

    def __init__(self, live: LiveRun, host: str = "127.0.0.1", port: int = 8080) -> None:
        self.live = live
        super().__init__(live.replay, host=host, port=port)
        self.available = max(live.done, 1)
        self.follow = self.server.gui.add_checkbox("follow the run", initial_value=True)
        self._follower = threading.Thread(target=self._follow, name="neurowalk-live", daemon=True)
        self._follower.start()

    def _follow(self) -> None:
        since = 0.0
        while not self._stop.wait(1.0 / FOLLOW_HZ):
            done = self.live.done
            if done == 0:
                continue
            grew = done != self.available
            self.available = done
            since += 1.0 / FOLLOW_HZ
            if grew and since >= TRACES_EVERY_S:
                since = 0.0
                self.refresh_traces()
                self._whole_path()
            if grew and self.follow.value:
                self.go(done - 1)

    def _whole_path(self) -> None:
        pts = self.replay.path[: self.available : max(1, self.available // 1500)]
        if len(pts) >= 2:
            self.scene.whole.points = np.stack([pts[:-1], pts[1:]], axis=1)

    def finished(self) -> None:
        """The run has ended: draw everything it recorded."""
        self.available = max(self.live.done, 1)
        self.refresh_traces()
        self._whole_path()
        self.go(self.available - 1)
