"""Headless Chromium driven over the DevTools protocol: open a page, press keys, read the DOM, take screenshots.

Used by the viewer's browser tests (a page is looked at and operated as a person would: the slider moved with the
keyboard, the picture compared); the websocket client is the ``websockets`` package, which viser depends on.
"""

from __future__ import annotations

import base64
import io
import itertools
import json
import os
import re
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib import image
from site_check import CHROMIUM, FLAGS, end_group  # software WebGL: the viewer's scene draws on a machine without a GPU
from websockets.sync.client import connect


class Browser:
    """One headless Chromium with one page (a context manager)."""

    def __init__(self, width: int = 1400, height: int = 900) -> None:
        self._profile = tempfile.TemporaryDirectory()
        # its temporary files too (a stopped Chromium leaves its org.chromium.Chromium.* folder there): removed with it
        env = {**os.environ, "TMPDIR": self._profile.name}
        self._proc = subprocess.Popen(
            [CHROMIUM, *FLAGS, f"--window-size={width},{height}", "--remote-debugging-port=0",
             f"--user-data-dir={self._profile.name}", "--allow-file-access-from-files", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env, start_new_session=True,
        )  # fmt: skip
        endpoint = self._endpoint()
        port = re.search(r":(\d+)/", endpoint).group(1)  # type: ignore[union-attr]
        page = next(t for t in self._targets(port) if t["type"] == "page")
        self._ws = connect(page["webSocketDebuggerUrl"], max_size=None)
        self._ids = itertools.count(1)
        self.send("Page.enable")
        self.send("Emulation.setDeviceMetricsOverride", width=width, height=height, deviceScaleFactor=1, mobile=False)

    def _endpoint(self) -> str:
        deadline = time.monotonic() + 30
        assert self._proc.stderr is not None
        while time.monotonic() < deadline:
            line = self._proc.stderr.readline()
            if "DevTools listening on" in line:
                return line.split("on", 1)[1].strip()
        raise RuntimeError("chromium did not start its DevTools endpoint")

    @staticmethod
    def _targets(port: str) -> list[dict[str, Any]]:
        from urllib.request import urlopen

        with urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as f:
            return json.loads(f.read())

    def send(self, method: str, **params: Any) -> dict[str, Any]:
        """Call a DevTools method and return its result (events that arrive meanwhile are dropped)."""
        i = next(self._ids)
        self._ws.send(json.dumps({"id": i, "method": method, "params": params}))
        while True:
            msg = json.loads(self._ws.recv(timeout=60))
            if msg.get("id") == i:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})

    def open(self, url: str, settle_s: float = 4.0) -> None:
        """Load ``url`` and give its scripts ``settle_s`` s to draw."""
        self.send("Page.navigate", url=url)
        time.sleep(settle_s)

    def evaluate(self, expression: str) -> Any:
        """The value of a JavaScript expression on the page."""
        out = self.send("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        return out.get("result", {}).get("value")

    def wait_for(self, expression: str, timeout_s: float = 30.0) -> None:
        """Wait until a JavaScript expression is true on the page."""
        deadline = time.monotonic() + timeout_s
        while not self.evaluate(expression):
            if time.monotonic() > deadline:
                raise TimeoutError(f"not true after {timeout_s} s: {expression}")
            time.sleep(0.25)

    def key(self, key: str, code: str, key_code: int) -> None:
        """Press and release one key on the focused element."""
        for kind in ("rawKeyDown", "keyUp"):
            self.send("Input.dispatchKeyEvent", type=kind, key=key, code=code, windowsVirtualKeyCode=key_code)

    def screenshot(self) -> np.ndarray:
        """The page as an (H, W, 3) float array in [0, 1]."""
        data = base64.b64decode(self.send("Page.captureScreenshot", format="png")["data"])
        return image.imread(io.BytesIO(data), format="png")[..., :3]

    def settled(self, timeout_s: float = 60.0) -> np.ndarray:
        """A screenshot once the page has stopped changing (two in a row alike but for a few pixels: a blinking
        caret, half a second apart)."""
        deadline = time.monotonic() + timeout_s
        last = self.screenshot()
        while time.monotonic() < deadline:
            time.sleep(0.5)
            now = self.screenshot()
            if changed(last, now) < 2e-5:
                return now
            last = now
        raise TimeoutError(f"the page still changed after {timeout_s} s")

    def save(self, picture: np.ndarray, path: Path) -> None:
        """Write a screenshot for a person to look at."""
        image.imsave(path, picture)

    def close(self) -> None:
        """Stop Chromium and every process it started (its group), then remove its profile: a renderer still writing
        into the profile would keep it from being removed."""
        self._ws.close()
        self._proc.terminate()
        self._proc.wait(timeout=10)
        end_group(self._proc.pid)
        self._profile.cleanup()

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def changed(a: np.ndarray, b: np.ndarray, box: tuple[float, float, float, float] = (0, 0, 1, 1)) -> float:
    """The share of pixels that differ between screenshots ``a`` and ``b`` inside ``box`` (x0, y0, x1, y1 as shares
    of the width and height)."""
    h, w = a.shape[:2]
    ys, xs = slice(int(box[1] * h), int(box[3] * h)), slice(int(box[0] * w), int(box[2] * w))
    return float(np.mean(np.any(np.abs(a[ys, xs] - b[ys, xs]) > 0.05, axis=-1)))
