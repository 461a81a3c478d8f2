"""The `view` command: a run's 3-D replay in the browser (served, or written as one HTML file), or a run live in
MuJoCo's own viewer on a desktop (`--native`)."""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from pathlib import Path
from typing import TYPE_CHECKING

from neurowalk.cli.common import UsageError, episode_args, episode_config, failed, usage_errors

if TYPE_CHECKING:
    from neurowalk.plotting.live import LivePage
    from neurowalk.sim.config import EpisodeConfig
    from neurowalk.sim.trajectory import PartWriter

LOCAL = "127.0.0.1"


def add_view_parser(sub: argparse._SubParsersAction) -> None:
    """The `view` subcommand."""
    v = sub.add_parser(
        "view",
        help="a run's 3-D replay with its neural traces in the browser (RUN_DIR), or a run live in MuJoCo's "
        "viewer (--native, needs a display)",
    )
    v.add_argument(
        "run_dir", nargs="?", type=Path, metavar="RUN_DIR", help="a run's output folder, as `neurowalk run` writes it"
    )
    web_args(v)
    v.add_argument("--export", type=Path, metavar="FILE.html", help="write the replay as one HTML file and exit")
    v.add_argument(
        "--native",
        action="store_true",
        help="run the settings below live in MuJoCo's own viewer (needs a display) instead of replaying RUN_DIR",
    )
    episode_args(v)


def web_args(p: argparse.ArgumentParser) -> None:
    """The page's flags (`view`, `run --web`): --port and --host."""
    p.add_argument("--port", type=int, default=8080, help="the page's port (default 8080)")
    p.add_argument(
        "--host",
        default=LOCAL,
        help=f"the address to serve on (default {LOCAL}: this machine only; 0.0.0.0: every network interface)",
    )


def check_web(args: argparse.Namespace, serve: bool = True) -> None:
    """UsageError, before any work, where the page cannot be served (``serve``; else only written, as `view
    --export` does): no viser, a bad or taken port or host."""
    if serve and not 0 < args.port < 65536:
        raise UsageError(f"--port must be 1-65535, got {args.port}")
    from neurowalk.plotting.web import PortError, check_port, require_viser

    try:
        require_viser()
        if serve:
            check_port(args.host, args.port)
    except ImportError as e:
        raise UsageError(str(e)) from None
    except PortError as e:
        raise UsageError(f"{e} (choose another with --port, or --host)") from None


def _serving(what: str, args: argparse.Namespace) -> str:
    """The line that says where the page is."""
    where = "this machine only" if args.host == LOCAL else f"every client that reaches {args.host}"
    return (
        f"serving {what} on http://{args.host}:{args.port} ({where}; from another machine: "
        f"ssh -L {args.port}:localhost:{args.port} THIS_HOST, then open http://localhost:{args.port})"
    )


def live_page(cfg: EpisodeConfig, parts: PartWriter, args: argparse.Namespace) -> LivePage:
    """`run --web`'s page: a live view of the run (the rows go on to ``parts``), served from now on."""
    from neurowalk.plotting.live import LivePage, LiveRun

    page = LivePage(LiveRun(cfg, then=parts), host=args.host, port=args.port)
    print(f"neurowalk: {_serving('the run live', args)}", file=sys.stderr, flush=True)
    return page


def keep_serving(page: LivePage, args: argparse.Namespace) -> None:
    """After `run --web`'s run: the page shows the whole run until Ctrl-C."""
    page.finished()
    _wait_for_stop(f"neurowalk: the run is done; its replay stays on http://{args.host}:{args.port}: Ctrl-C stops")


def cmd_view(args: argparse.Namespace) -> int:
    """`neurowalk view`: the replay of RUN_DIR on a page until Ctrl-C (exit 0), or written to ``--export``."""
    if args.native:
        if args.run_dir is not None:
            raise UsageError(f"view --native runs the settings given live, not a run's folder: drop {args.run_dir}")
        return _native(args)
    if args.run_dir is None:
        raise UsageError("view needs RUN_DIR, a run's folder (or --native to watch a run live on a desktop)")
    if args.export is not None and args.export.suffix.lower() not in (".html", ".htm"):
        raise UsageError(f"--export writes an HTML file: name it FILE.html, got {str(args.export)!r}")
    if args.export is not None and not args.export.resolve().parent.is_dir():
        raise UsageError(f"--export {str(args.export)!r}: its folder does not exist")
    check_web(args, serve=args.export is None)
    from neurowalk.plotting.replay import RunFolderError, load_replay
    from neurowalk.plotting.web import ReplayPage, export_html

    with usage_errors(RunFolderError):
        replay = load_replay(args.run_dir)
    if args.export is not None:
        size = export_html(replay, args.export)
        print(f"wrote {args.export} ({size / 1e6:.1f} MB): the replay of {args.run_dir}, plays with no server")
        return 0
    page = ReplayPage(replay, host=args.host, port=args.port)
    print(f"{_serving(f'the replay of {args.run_dir}', args)}; Ctrl-C stops", flush=True)
    _wait_for_stop()
    page.close()
    return 0


def _wait_for_stop(line: str | None = None) -> None:
    """Block until SIGINT or SIGTERM; ``line`` (to stderr) once the handlers are in place, so that a stop sent as soon
    as it is read is answered here, not as an interrupt of what came before."""
    stop = threading.Event()
    old = {sig: signal.signal(sig, lambda *_: stop.set()) for sig in (signal.SIGINT, signal.SIGTERM)}
    if line is not None:
        print(line, file=sys.stderr, flush=True)
    try:
        while not stop.wait(0.5):
            pass
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)


def _native(args: argparse.Namespace) -> int:
    """`neurowalk view --native`: the settings run live in MuJoCo's viewer."""
    from neurowalk.body.registry import bodies_where
    from neurowalk.render import has_display, view

    cfg = episode_config(args)
    viewable = bodies_where(lambda b: b.viewer)
    if args.body not in viewable:
        raise UsageError(f"view needs --body {' or '.join(viewable)}, got {args.body!r}")
    if not has_display():
        return failed(
            "neurowalk view: no display here (DISPLAY is not set); use `neurowalk run --video` for a headless video"
        )
    from neurowalk.sim.episode import build, seeds

    _, body, ctrl = build(cfg)
    body_rng, ctrl_rng, _ = seeds(cfg)
    body.reset(body_rng)
    ctrl.reset(ctrl_rng)

    def step() -> None:
        body.apply(ctrl.act(body.observe()))
        body.advance()

    view(body.model, body.data, step, control_hz=body.control_hz)
    return 0
