"""The documentation site as a reader's browser shows it: every page loaded in headless Chromium (Debian's
``chromium``), with what a person would see wrong reported.

For each page of a built site (``mkdocs build``), served on ``127.0.0.1``: no request of the page fails (an image, a
script, a style sheet: the server records every path it could not serve), nothing is written to the browser's
console (a script error, a failed load), no Mermaid diagram is left as its source text, and every link to another
page of the site names a file that is there. Screenshots of the home page, a tutorial and the report are written
for a person to look at.
"""

from __future__ import annotations

import functools
import html
import http.server
import os
import re
import shutil
import signal
import subprocess
import tempfile
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from urllib.parse import unquote, urljoin, urlparse

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
#: Software WebGL (SwiftShader): the gallery's replays draw with it, where --disable-gpu left their pages hanging.
FLAGS = [
    "--headless=new",
    "--no-sandbox",
    "--hide-scrollbars",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
]
#: What the replays' client (viser's, in the gallery's frames) says on every load: its own notes, not faults.
VISER_NOTES = re.compile(
    r'^"(?:Detected chrome version \d+|WebGL support: true,.*|Embedded data loaded! Saved with Viser version: [\d.]+'
    r'|THREE\.Clock: This module has been deprecated\..*|\[Performance\] Setting DPR to [\d.]+; FPS=[\d/]+)"'
)
SCREENSHOTS = {"home": "", "tutorial": "tutorials/study/", "report": "results/report/"}
#: A Mermaid diagram's source keyword: once drawn, the page's DOM holds the picture, not these words.
MERMAID_SOURCE = re.compile(r"<(?:pre|div)[^>]*mermaid[^>]*>\s*(?:<code>)?\s*(?:flowchart|graph|sequenceDiagram)\b")


class _Handler(http.server.SimpleHTTPRequestHandler):
    missing: list[str]

    def send_error(self, code: int, message: str | None = None, explain: str | None = None) -> None:
        self.missing.append(f"{code} {self.path}")
        super().send_error(code, message, explain)

    def log_message(self, *args: object) -> None:  # quiet
        pass


@contextmanager
def serve(site: Path) -> Iterator[tuple[str, list[str]]]:
    """The site served on a free port of 127.0.0.1: (its base URL, the requests it could not serve, as they come)."""
    missing: list[str] = []
    handler = type("Handler", (_Handler,), {"missing": missing})
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(handler, directory=str(site)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/", missing
    finally:
        server.shutdown()
        server.server_close()


def pages(site: Path) -> list[str]:
    """The site's pages (paths relative to its root: ``""``, ``usage/``, ...), the search and 404 pages aside."""
    out = []
    for index in sorted(site.rglob("index.html")):
        rel = index.parent.relative_to(site).as_posix()
        if not rel.startswith(("assets", "search")):
            out.append("" if rel == "." else rel + "/")
    return out


def alive_in_group(pgid: int) -> list[int]:
    """The processes of process group ``pgid`` that have not ended (zombies, which write nothing, left out), from
    ``/proc``: Chromium's renderer, GPU and utility processes outlive its main process for a moment."""
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:  # ended while read
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":  # fields: state, ppid, pgrp, ...
            out.append(int(stat.parent.name))
    return out


def end_group(pgid: int, timeout_s: float = 20.0) -> None:
    """End every process of Chromium's process group ``pgid`` (its main process started it with
    ``start_new_session``) and wait until none is left: a profile removed while one of them still writes into it
    is not removed ("Directory not empty"). SIGTERM first, SIGKILL after half of ``timeout_s``."""
    deadline = time.monotonic() + timeout_s
    for sig in (signal.SIGTERM, signal.SIGKILL):
        try:
            os.killpg(pgid, sig)
        except ProcessLookupError:
            return
        until = deadline - timeout_s / 2 if sig == signal.SIGTERM else deadline
        while time.monotonic() < until:
            if not alive_in_group(pgid):
                return
            time.sleep(0.05)
    raise RuntimeError(f"chromium's processes {alive_in_group(pgid)} did not end in {timeout_s:g} s")


def chromium(args: list[str], timeout: float = 120.0, **kw: object) -> subprocess.CompletedProcess:
    """Run headless Chromium with ``args`` in a profile and temporary folder of its own, removed when it and every
    process it started have ended (the user's profile is not touched, and nothing of Chromium's stays in the
    temporary folder). ``kw``: as :func:`subprocess.Popen`'s (``capture_output``, ``text``)."""
    if kw.pop("capture_output", False):
        kw["stdout"] = kw["stderr"] = subprocess.PIPE
    with tempfile.TemporaryDirectory(prefix="chromium-") as own:
        env = {**os.environ, "TMPDIR": own}
        cmd = [CHROMIUM, *FLAGS, f"--user-data-dir={own}", *args]
        proc = subprocess.Popen(cmd, env=env, start_new_session=True, **kw)  # type: ignore[call-overload]
        try:
            out, err = proc.communicate(timeout=timeout)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
            end_group(proc.pid)
        return subprocess.CompletedProcess(cmd, proc.returncode, out, err)


def load(url: str, budget_ms: int = 6000) -> tuple[str, list[str]]:
    """The page's DOM once its scripts ran (``budget_ms`` of virtual time) and the lines it wrote to the console."""
    args = ["--enable-logging=stderr", "--v=0", f"--virtual-time-budget={budget_ms}", "--dump-dom", url]
    done = chromium(args, capture_output=True, text=True, timeout=120)
    console = [line.split("] ", 1)[-1] for line in done.stderr.splitlines() if ":CONSOLE" in line]
    console = [line for line in console if not VISER_NOTES.match(line)]
    return done.stdout, console


def problems(site: Path, base: str, page: str, missing: list[str]) -> list[str]:
    """What is wrong with ``page`` as the browser shows it (empty: nothing)."""
    before = len(missing)
    dom, console = load(base + page)
    found = [f"console: {line}" for line in console]
    found += [f"not served: {m}" for m in missing[before:]]
    if not dom.strip():
        found.append("the page did not load")
    if MERMAID_SOURCE.search(dom):
        found.append("a Mermaid diagram shown as its source text")
    for href in re.findall(r'<a [^>]*href="([^"]+)"', dom):
        target = urlparse(urljoin(base + page, html.unescape(href)))
        if target.netloc != urlparse(base).netloc:
            continue
        path = site / unquote(target.path).lstrip("/")
        path = path / "index.html" if path.is_dir() else path
        if not path.is_file():
            found.append(f"link to a missing page: {href}")
        elif target.fragment and path.suffix == ".html":
            text = dom if path == site / page / "index.html" else path.read_text(encoding="utf-8")
            if f'id="{unquote(target.fragment)}"' not in text:
                found.append(f"link to a missing place on its page: {href}")
    return [f"{page or '/'}: {p}" for p in found]


def screenshots(base: str, out: Path) -> list[Path]:
    """PNGs of the home page, a tutorial and the report in ``out``, for a person to look at."""
    out.mkdir(parents=True, exist_ok=True)
    shots = []
    for name, page in SCREENSHOTS.items():
        path = out / f"{name}.png"
        chromium(["--window-size=1400,2200", f"--screenshot={path}", base + page], capture_output=True, timeout=120)
        shots.append(path)
    return shots
