"""A run in the browser: a 3-D replay with the network's traces beside it, served by viser, or one HTML file.

:class:`ReplayPage` draws a :class:`~neurowalk.plotting.replay.Replay` on a viser server: the arena and the robot
as their meshes, the trunk's path so far, the two ultrasonic rays coloured by their input (green far, red near),
and beside the scene a time slider with play, pause and speed (1x to 100x real time), the simulated time, the
inputs I1/I2, outputs O1/O2 and weights b1, b2, c over the whole run with a marker at the moment shown, and the
run's outcome with a button per wedged period. Clicking the path moves the replay to the moment the trunk was
there. :func:`export_html` writes the replay as one self-contained HTML file (viser's scene recording and its
client: it plays with no server), with a picture of the traces in a corner.

viser is the ``web`` extra; it is imported here only, and :func:`require_viser` says how to install it.
"""

from __future__ import annotations

import base64
import contextlib
import io
import socket
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from neurowalk.fileio import atomic_write
from neurowalk.plotting.replay import Part, Replay
from neurowalk.plotting.runs import draw_traces
from neurowalk.plotting.style import look

try:  # the optional extra, behind this one guarded import
    import viser
except ImportError as _err:  # pragma: no cover - exercised where the extra is missing
    viser = None
    _VISER_ERROR: ImportError | None = _err
else:
    _VISER_ERROR = None

#: Replay speeds offered, in multiples of real time.
SPEEDS = (1, 2, 5, 10, 20, 50, 100)
#: Points of each trace sent to the page (a longer run is shown every k-th step).
TRACE_POINTS = 800
#: Points of the path drawn (a longer run's path is thinned to these).
PATH_POINTS = 1500
FAR, NEAR = np.array([40, 170, 60]), np.array([220, 40, 40])  # ray colours at I = -1 and I = +1
PATH_RGB = (90, 60, 160)  # the path walked so far
TRACE_COLOURS = ("#1f77b4", "#ff7f0e", "#222222")
PLAY_HZ = 20.0  # frames per second of wall time while playing


def require_viser() -> Any:
    """viser, or ImportError saying how to install it (``pip install -e '.[web]'`` in neurowalk's folder)."""
    if viser is None:
        raise ImportError(f"the web viewer needs viser: pip install -e '.[web]' in neurowalk's folder ({_VISER_ERROR})")
    return viser


class PortError(OSError):
    """The page's port cannot be had (in use, or not allowed): the message names the host and port."""


def check_port(host: str, port: int) -> None:
    """Raise :class:`PortError` where ``host:port`` cannot be bound now (viser would move to another port)."""
    with socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_STREAM) as s:
        try:
            s.bind((host, port))
        except OSError as e:
            raise PortError(f"cannot serve on {host}:{port}: {e.strerror or e}") from None


def free_port(host: str = "127.0.0.1") -> int:
    """A port on ``host`` that nothing listens on now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


def ray_colours(inputs: np.ndarray) -> np.ndarray:
    """(..., 3) uint8 colours of rays whose network inputs are ``inputs`` (-1 far: green, +1 near: red)."""
    u = (np.clip(np.asarray(inputs, dtype=float), -1.0, 1.0)[..., None] + 1.0) / 2.0
    return np.round(FAR + u * (NEAR - FAR)).astype(np.uint8)


def _thin(n: int, most: int) -> np.ndarray:
    """Indices of at most ``most`` of ``n`` rows, evenly spaced, the last one included."""
    return np.unique(np.append(np.arange(0, n, max(1, int(np.ceil(n / most)))), n - 1))


def _mesh(scene: Any, name: str, part: Part, **pose: Any) -> Any:
    """Add ``part`` to viser ``scene`` as mesh ``name`` (opaque unless its colour says otherwise)."""
    opacity = part.opacity if part.opacity < 1 else None
    return scene.add_mesh_simple(name, part.mesh.vertices, part.mesh.faces, color=part.rgb, opacity=opacity, **pose)


def start_server(host: str, port: int) -> Any:
    """A viser server on ``host:port``, quiet (viser prints a banner on stdout, which a command's output is not),
    without viser's share button (it would publish the page through viser's public relay)."""
    with contextlib.redirect_stdout(io.StringIO()):
        server = require_viser().ViserServer(host=host, port=port, verbose=False)
    server.gui.configure_theme(show_share_button=False, show_logo=False)
    return server


def stop_server(server: Any) -> None:
    """Stop ``server`` (quietly: viser says so on stdout)."""
    with contextlib.redirect_stdout(io.StringIO()):
        server.stop()


class Scene:
    """The 3-D part of a replay on a viser server (or on a scene recording): parts, path and rays, posed at a step."""

    def __init__(self, server: Any, replay: Replay) -> None:
        self.replay = replay
        scene = server.scene
        scene.set_up_direction("+z")
        xy = np.concatenate(
            [replay.path[:, :2], *(part.mesh.vertices[:, :2] + pos[:2] for part, pos, _ in replay.fixed)]
        )
        lo, hi = np.nanmin(xy, axis=0), np.nanmax(xy, axis=0)
        centre, reach = (lo + hi) / 2, max(float(np.max(hi - lo)), 1.0)
        aim = (centre[0] + 0.2 * reach, centre[1], 0.0)  # right of the middle: the control panel covers the right
        server.initial_camera.look_at = aim
        server.initial_camera.position = (aim[0] - 0.1 * reach, aim[1] - 0.7 * reach, 0.6 * reach)
        scene.add_grid("/floor", width=40.0, height=40.0, cell_size=0.5, position=(0.0, 0.0, -0.001))
        for i, (part, pos, quat) in enumerate(replay.fixed):
            _mesh(scene, f"/arena/{i}", part, position=pos, wxyz=quat)
        self.parts = [_mesh(scene, f"/robot/{p.name}", p) for p in replay.parts]
        self.path_rows = _thin(replay.steps, PATH_POINTS)
        pts = replay.path[self.path_rows]
        whole = np.stack([pts[:-1], pts[1:]], axis=1)
        self.whole = scene.add_line_segments("/path/whole", whole, colors=(200, 200, 220), thickness=0.004)
        self.path = scene.add_line_segments("/path/done", whole[:1], colors=PATH_RGB, thickness=0.012)
        self.rays = scene.add_line_segments("/rays", self._ray_points(0), colors=self._ray_colours(0), thickness=0.01)

    def _ray_points(self, frame: int) -> np.ndarray:
        return np.stack([self.replay.ray_from[frame], self.replay.ray_to[frame]], axis=1)

    def _ray_colours(self, frame: int) -> np.ndarray:
        step = int(self.replay.frames[frame])
        return np.repeat(ray_colours(self.replay.inputs[step])[:, None, :], 2, axis=1)

    def show(self, step: int) -> None:
        """Pose everything as at control step ``step``."""
        r = self.replay
        f = r.frame_of_step(step)
        for k, handle in enumerate(self.parts):
            handle.position, handle.wxyz = r.pos[f, k], r.quat[f, k]
        done = r.path[np.append(self.path_rows[self.path_rows < step], step)]
        if len(done) < 2:
            done = np.repeat(done[:1], 2, axis=0)
        self.path.points = np.stack([done[:-1], done[1:]], axis=1)
        self.rays.points = self._ray_points(f)
        self.rays.colors = self._ray_colours(f)

    def nearest_step(self, origin: np.ndarray, direction: np.ndarray, within: float = 0.3) -> int | None:
        """The step at which the trunk was nearest to where a click's ray meets the path's height, where that is
        within ``within`` m of the path (else None)."""
        z = float(np.nanmedian(self.replay.path[:, 2]))
        if abs(direction[2]) < 1e-9:
            return None
        s = (z - origin[2]) / direction[2]
        if s <= 0:
            return None
        hit = origin[:2] + s * direction[:2]
        gap = np.linalg.norm(self.replay.path[:, :2] - hit, axis=1)
        step = int(np.nanargmin(gap))
        return step if gap[step] <= within else None


def y_ticks(lo: float, hi: float) -> list[float]:
    """Three to five round values inside [``lo``, ``hi``] for a trace panel's y axis."""
    for nbins in (4, 5, 6, 8):  # the coarsest round step that leaves three inside
        ticks = [float(round(t, 10)) for t in MaxNLocator(nbins, steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi)]
        inside = [t for t in ticks if lo <= t <= hi]
        if len(inside) >= 3:
            return inside[:5]
    return inside


def _traces(r: Replay) -> list[tuple[str, list[str], np.ndarray]]:
    """(title, labels, (T, n) values) of each trace panel: inputs, outputs, weights (where they learn)."""
    panels = [
        ("inputs I", ["I1 (left)", "I2 (right)"], r.inputs),
        ("outputs O", ["O1 (left)", "O2 (right)"], r.outputs),
    ]
    if np.isfinite(r.b).any():
        c = -(r.q[:, 0] + r.q[:, 1]) / 2
        panels.append(("weights", ["b1 (left)", "b2 (right)", "c = -(q1 + q2)/2"], np.column_stack([r.b, c])))
    return panels


class ReplayPage:
    """A replay served as a page (see the module doc): ``show(step)`` moves it, as the slider does."""

    def __init__(self, replay: Replay, host: str = "127.0.0.1", port: int = 8080) -> None:
        check_port(host, port)
        self.replay = replay
        self.server = start_server(host, port)
        self.scene = Scene(self.server, replay)
        self._lock = threading.Lock()
        self._playing = threading.Event()
        self._stop = threading.Event()
        self.available = replay.steps  # steps that can be shown (a live run's grow)
        self._rows = _thin(replay.steps, TRACE_POINTS)
        self._y: dict[str, tuple[float, float]] = {}
        self._build_gui()
        self.show(0)
        self._player = threading.Thread(target=self._play, name="neurowalk-replay", daemon=True)
        self._player.start()

    def _build_gui(self) -> None:
        gui, r = self.server.gui, self.replay
        gui.add_markdown(f"**{r.title}**")
        self.clock = gui.add_markdown("")
        self.slider = gui.add_slider("step", min=0, max=max(r.steps - 1, 1), step=1, initial_value=0)
        self.slider.on_update(lambda _: self.show(int(self.slider.value)))
        self.play = gui.add_button("play / pause")
        self.play.on_click(lambda _: self._playing.clear() if self._playing.is_set() else self._playing.set())
        self.speed = gui.add_dropdown("speed", [f"{s}x" for s in SPEEDS], initial_value="10x")
        self.plots = []
        for title, labels, values in _traces(r):
            series = [{"label": "time (s)"}]
            series += [{"label": lab, "stroke": TRACE_COLOURS[i], "width": 1.5} for i, lab in enumerate(labels)]
            series.append({"label": "now", "stroke": "#d62728", "width": 0, "points": {"show": True, "size": 10}})
            data, scales, axes = self._panel(title, values)
            plot = gui.add_uplot(data, tuple(series), title=title, scales=scales, axes=axes, aspect=2.2)
            self.plots.append((title, plot, values))
        self._outcome(gui)
        self.server.scene.on_click()(self._clicked)

    def _panel(self, title: str, values: np.ndarray) -> tuple[tuple[np.ndarray, ...], dict[str, Any], tuple]:
        """The data (time, each trace, the marker), scales and axes of trace panel ``title`` over the steps
        available: the y axis ticked at :func:`y_ticks` (uPlot's own choice on a short panel is one tick, 0)."""
        rows = self._rows
        shown = np.where(np.isfinite(values[rows]), values[rows], 0.0)  # uPlot draws no line through NaN
        lo, hi = float(shown.min()), float(shown.max())
        pad = 0.05 * (hi - lo) + 1e-3
        self._y[title] = (lo - pad, hi + pad)
        data = (self.replay.t[rows], *shown.T, self._marker(title, 0, float(shown[0, 0])))
        scales = {"x": {"time": False}, "y": {"auto": False, "range": list(self._y[title])}}
        axes = ({}, {"splits": y_ticks(*self._y[title])})
        return tuple(np.asarray(d, dtype=float) for d in data), scales, axes

    def refresh_traces(self) -> None:
        """Draw the traces again over the steps available now (a live run's grow)."""
        self._rows = _thin(max(self.available, 1), TRACE_POINTS)
        with self._lock, self.server.atomic():
            for title, plot, values in self.plots:
                plot.data, plot.scales, plot.axes = self._panel(title, values)

    def _outcome(self, gui: Any) -> None:
        s, r = self.replay.summary, self.replay
        lines = []
        if s.get("escaped") is not None:
            at = s.get("exit_step")
            lines.append(f"escaped at {at / r.control_hz:.0f} s" if s["escaped"] and at is not None else "not escaped")
        if s.get("trapped") is not None:
            lines.append("trapped at the end" if s["trapped"] else "not trapped at the end")
        if s.get("coverage") is not None:
            lines.append(f"coverage {100 * float(s['coverage']):.1f}% of the free cells")
        lines.append(f"{len(r.wedged)} wedged period(s); click the path to go to that moment")
        gui.add_markdown("  \n".join(lines))
        for i, (a, b) in enumerate(r.wedged):
            button = gui.add_button(f"wedged {i + 1}: {a / r.control_hz:.0f}-{b / r.control_hz:.0f} s")
            button.on_click(lambda _, a=a: self.go(a))

    def _marker(self, title: str, step: int, value: float) -> np.ndarray:
        """The "now" series of trace panel ``title``: ``value`` at ``step``'s point, elsewhere far off the panel's
        y range, where uPlot draws nothing (it draws no point for NaN either, but then finds no range at all)."""
        lo, hi = self._y[title]
        marker = np.full(len(self._rows), hi + 1e3 * (hi - lo))
        marker[min(int(np.searchsorted(self._rows, step)), len(self._rows) - 1)] = value
        return marker

    def _clicked(self, event: Any) -> None:
        step = self.scene.nearest_step(np.asarray(event.ray_origin), np.asarray(event.ray_direction))
        if step is not None:
            self.go(step)

    def go(self, step: int) -> None:
        """Move the replay (and the slider) to control step ``step`` (at most the last one available)."""
        self.slider.value = int(np.clip(step, 0, max(self.available - 1, 0)))

    def show(self, step: int) -> None:
        """Draw control step ``step``: the scene, the clock and each trace's marker."""
        r = self.replay
        step = int(np.clip(step, 0, max(self.available - 1, 0)))
        with self._lock, self.server.atomic():
            self.scene.show(step)
            self.clock.content = f"t = {r.t[step]:.1f} s (step {step} of {self.available})"
            for title, plot, values in self.plots:
                plot.data = (*plot.data[:-1], self._marker(title, step, values[step, 0]))

    def _play(self) -> None:
        last = time.perf_counter()
        while not self._stop.wait(1.0 / PLAY_HZ):
            now = time.perf_counter()
            if self._playing.is_set():
                speed = float(self.speed.value.rstrip("x"))
                step = int(self.slider.value) + max(1, round(speed * self.replay.control_hz * (now - last)))
                if step >= self.available:
                    self._playing.clear()
                    step = self.available - 1
                self.go(step)
            last = now

    def close(self) -> None:
        """Stop playing and shut the server down (once; closing again does nothing)."""
        if not self._stop.is_set():
            self._stop.set()
            stop_server(self.server)


def traces_png(replay: Replay) -> bytes:
    """The run's traces over the whole run as a PNG picture (inputs, outputs and, where they learn, the weights), as
    ``run.png`` draws them."""
    plastic = bool(np.isfinite(replay.b).any())
    fig = Figure(figsize=(5.2, 4.2 if plastic else 3.0), dpi=100, layout="constrained")
    signals = [(replay.inputs, "I", "input I"), (replay.outputs, "O", "steering O")]
    draw_traces(fig, fig.add_gridspec(1, 1)[0], replay.t, signals, replay.b, replay.q, "", plastic=plastic)
    buf = io.BytesIO()
    with look():
        fig.savefig(buf, format="png")
    return buf.getvalue()


def with_traces(html: str, png: bytes) -> str:
    """viser's exported page ``html`` with the picture ``png`` of the run's traces fixed in its lower left corner."""
    panel = (
        '<figure id="neurowalk-traces" style="position:fixed;left:12px;bottom:12px;width:min(440px,38vw);margin:0;'
        'padding:6px;background:#fff;border:1px solid #ccc;border-radius:6px;z-index:10;font:12px sans-serif">'
        f'<img alt="the run\'s inputs, outputs and weights over time" style="width:100%" '
        f'src="data:image/png;base64,{base64.b64encode(png).decode()}"/>'
        "<figcaption>The run's inputs, outputs and weights over the whole run (the served page, <code>neurowalk "
        "view RUN_DIR</code>, marks the moment shown).</figcaption></figure>"
    )
    head, tail = html.rsplit("</body>", 1)
    return f"{head}{panel}\n</body>{tail}"


def export_html(replay: Replay, path: str | Path, speed: float = 10.0, fps: float = 10.0) -> int:
    """Write ``path``: one HTML file that plays ``replay`` at ``speed`` times real time, ``fps`` frames per second,
    with no server (viser's scene recording inside its client), the run's traces beside it (:func:`traces_png`).
    Returns the file's size in bytes."""
    server = start_server("127.0.0.1", free_port())
    try:
        scene = Scene(server, replay)
        scene.show(0)
        recording = server.get_scene_serializer()
        step_per_frame = max(1, round(speed * replay.control_hz / fps))
        for step in range(0, replay.steps, step_per_frame):
            scene.show(step)
            recording.insert_sleep(1.0 / fps)
        scene.show(replay.steps - 1)
        html = with_traces(recording.as_html(), traces_png(replay))
    finally:
        stop_server(server)
    atomic_write(Path(path), lambda tmp: Path(tmp).write_text(html, encoding="utf-8"))
    return len(html.encode())
