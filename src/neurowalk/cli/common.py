"""What several commands share: the usage error, the parser class, output path checks, the episode arguments."""

from __future__ import annotations

import argparse
import contextlib
import sys
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from neurowalk.fileio import make_writable_folder
from neurowalk.runners.stopping import interrupted, stop_status

if TYPE_CHECKING:
    from neurowalk.sim.config import EpisodeConfig
    from neurowalk.sim.engine_interface import EngineOptions


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


class Parser(argparse.ArgumentParser):
    """The parser of the command and of each subcommand: a bad command line raises UsageError.

    Every option of ``type=Path`` takes a non-empty name (:func:`path_value`): ``Path("")`` is the working folder,
    so ``--out ''`` would write there. ``{NAME}`` in an option's help is the names of registry NAME
    (:func:`registry_names`), looked up only when help is shown.
    """

    help_tail: Callable[[], str] | None = None  # more help, computed only when help is asked for
    hidden = False  # the options added now are hidden from the help (e.g. the settings a study does not take)

    def error(self, message: str) -> NoReturn:  # one clear line instead of usage + message
        raise UsageError(message)

    def add_argument(self, *args: Any, **kwargs: Any) -> argparse.Action:
        if kwargs.get("type") is Path:
            kwargs["type"] = path_value
        if self.hidden:
            kwargs["help"] = argparse.SUPPRESS
        return super().add_argument(*args, **kwargs)

    def format_help(self) -> str:
        for action in self._actions:
            for name in REGISTRIES:
                if action.help and f"{{{name}}}" in action.help:
                    action.help = action.help.replace(f"{{{name}}}", " | ".join(registry_names(name)))
        return super().format_help() + (self.help_tail() if self.help_tail else "")


#: The registries whose names help text shows, and where each one's names are: the attribute of a module that holds
#: them (its keys, or what it returns where it is a function); ``physics_bodies`` are the bodies with a 3-D model.
_REGISTRY_SOURCES = {
    "variants": ("neurowalk.neural.variants", "variant_names"),
    "bodies": ("neurowalk.body.registry", "BODIES"),
    "physics_bodies": ("neurowalk.body.registry", "BODIES"),
    "calibrated_bodies": ("neurowalk.experiments.calibration.subjects", "SUBJECTS"),
    "arenas": ("neurowalk.arenas", "ARENAS"),
    "engines": ("neurowalk.sim.engines", "ENGINES"),
    "controllers": ("neurowalk.controller", "CONTROLLERS"),
    "gaits": ("neurowalk.neural.cpg", "GAITS"),
    "optimize_bases": ("neurowalk.experiments.optimize.space", "BASES"),
}
REGISTRIES = tuple(_REGISTRY_SOURCES)


def registry_names(name: str) -> tuple[str, ...]:
    """The names that registry ``name`` (one of :data:`REGISTRIES`) holds, as the checks of the values see them."""
    import importlib

    if name not in _REGISTRY_SOURCES:
        raise ValueError(f"unknown registry {name!r}; expected one of {', '.join(REGISTRIES)}")
    module, attribute = _REGISTRY_SOURCES[name]
    held = getattr(importlib.import_module(module), attribute)
    names = tuple(held() if callable(held) else held)
    if name == "physics_bodies":
        return tuple(b for b in names if held[b].physics)
    return tuple(sorted(names)) if name == "arenas" else names


@contextlib.contextmanager
def usage_errors(*errors: type[Exception]) -> Iterator[None]:
    """Inside the block an error of ``errors`` (default ValueError: a library's own check of a value) is bad input:
    UsageError with its message."""
    caught = errors or (ValueError,)
    try:
        yield
    except caught as e:
        raise UsageError(str(e)) from None


def path_value(text: str) -> Path:
    """The Path of a path option's value; refuses an empty or blank one, or one too long for any file system call
    (argparse names the option)."""
    if not text.strip():
        raise argparse.ArgumentTypeError(f"expects a file or folder name, got {text!r}")
    if too_long := path_too_long(Path(text)):
        raise argparse.ArgumentTypeError(too_long)
    return Path(text)


def shortened(text: str, most: int = 60) -> str:
    """``text`` quoted, its middle left out where it is longer than ``most`` characters (a value echoed in an
    error)."""
    if len(text) <= most:
        return repr(text)
    return f"{text[: most - 20] + '...' + text[-16:]!r} ({len(text):,} characters, shortened)"


def path_too_long(path: Path) -> str | None:
    """Why the system refuses ``path`` for its length (ENAMETOOLONG): a name in it over NAME_MAX bytes, or the whole
    over PATH_MAX; None where it is not too long."""
    import os

    try:
        name_max, path_max = os.pathconf("/", "PC_NAME_MAX"), os.pathconf("/", "PC_PATH_MAX")
    except (OSError, ValueError, AttributeError):  # no pathconf (Windows) or no such limit: the usual ones
        name_max, path_max = 255, 4096

    def size(text: str) -> int:  # bytes, as the system counts them
        try:
            return len(os.fsencode(text))
        except UnicodeEncodeError:  # a lone surrogate not from undecodable bytes
            return len(text.encode("utf-8", "surrogatepass"))

    longest = max(path.parts, key=size, default="")
    if size(longest) > name_max:
        return f"{shortened(str(path))}: a name in it is too long ({size(longest):,} bytes, at most {name_max:,})"
    if size(str(path)) >= path_max:
        return f"{shortened(str(path))}: the path is too long ({size(str(path)):,} bytes, at most {path_max - 1:,})"
    return None


def machine_memory() -> int | None:
    """Bytes of memory this machine (or the container's memory limit, where lower) has; None where unknown."""
    import os

    try:
        have = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):  # no sysconf (Windows) or no such name
        return None
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()  # cgroup v2; "max": no limit
    except OSError:
        return have
    return min(have, int(limit)) if limit.isdigit() else have


def _check_length(flag: str, *paths: Path) -> None:
    """UsageError naming ``flag`` and the first of ``paths`` too long for the system (:func:`path_too_long`)."""
    if too_long := next(filter(None, map(path_too_long, paths)), None):
        raise UsageError(f"{flag} {too_long}")


def out_folder(path: Path, flag: str = "--out", given: Path | None = None) -> Path:
    """Make the output folder ``path`` (and its parents); UsageError naming it if it is a file or cannot be written.

    ``given``: the path the user gave, named in the message (default ``path``; e.g. a file inside the folder).
    """
    _check_length(flag, given if given is not None else path, path)
    try:
        make_writable_folder(path)
    except ValueError as e:
        raise UsageError(f"{flag} {str(given if given is not None else path)!r}: {e}") from None
    return path


def out_file(path: Path, flag: str = "--out") -> Path:
    """Check that the output file ``path`` can be written (its folder made); UsageError naming it otherwise."""
    _check_length(flag, path)
    try:
        if path.is_dir():
            raise UsageError(f"{flag} {str(path)!r} is a folder; give a file name")
    except OSError as e:
        raise UsageError(f"{flag} {str(path)!r}: {e.strerror}") from None
    out_folder(path.parent if str(path.parent) else Path("."), flag, given=path)
    return path


def episode_args(p: argparse.ArgumentParser) -> None:
    """The flags of one closed-loop run (`run`, `view`)."""
    p.add_argument("--arena", default="open", help="{arenas} (default open; options: `neurowalk arenas`)")
    option_args(p, "--arena-opt", "KEY=VALUE", "arena option, repeatable")
    p.add_argument(
        "--controller",
        default="plastic",
        help="{controllers}, or FILE.py:NAME: a controller of your own (default plastic)",
    )
    p.add_argument("--steer", default=None, metavar="O1,O2", help="steering of controller 'fixed', e.g. -1,-1")
    p.add_argument(
        "--body",
        default="amosii",
        help="{bodies} | mjcf:FILE.xml (default amosii, the MuJoCo hexapod; see `neurowalk bodies`)",
    )
    option_args(p, "--body-opt", "KEY=VALUE", "body option, e.g. scale=0.5")
    p.add_argument("--steps", type=int, default=1000, help="control steps (default 1000: 100 s at 10 Hz)")
    control_hz_arg(p)
    p.add_argument("--seed", type=int, default=0, help="seed of every random draw (default 0)")
    p.add_argument("--reflexes", action="store_true", help="local leg control: searching and elevation reflexes")
    p.add_argument("--backbone", action="store_true", help="backbone joint control and climbable-step detection")
    p.add_argument("--climb", action="store_true", help="both --reflexes and --backbone (climbing)")
    variant_args(p)
    p.add_argument("--gait", default="wave", help="{gaits} (default wave)")


def option_args(p: argparse.ArgumentParser, flag: str, metavar: str, help: str) -> None:
    """A repeatable KEY=VALUE option ``flag`` (an arena's or a body's; :func:`parse_arena_opts` reads its items)."""
    p.add_argument(flag, action="append", default=[], metavar=metavar, help=help)


def backend_args(p: argparse.ArgumentParser) -> None:
    """--backend, --address and --workers: where the runs of a command of many runs run (`sweep`, `optimize`)."""
    p.add_argument(
        "--backend", choices=("local", "ray"), default="local", help="local process pool or Ray (default local)"
    )
    p.add_argument("--address", default=None, help="Ray cluster to join (backend ray; default: a local instance)")
    p.add_argument("--workers", type=int, default=2, help="processes, or CPUs of a local Ray instance (default 2)")


def check_address(args: argparse.Namespace) -> None:
    """UsageError where --address goes without --backend ray."""
    if args.address and args.backend != "ray":
        raise UsageError(f"--address {args.address!r} goes with --backend ray")


def count_args(p: argparse.ArgumentParser, counts: Sequence[tuple[str, str]]) -> None:
    """A whole-number option of each (flag name, help) of ``counts``: the sizes of a search, default its own."""
    for flag, what in counts:
        p.add_argument(f"--{flag}", type=int, default=None, help=what)


def counts_given(args: argparse.Namespace, counts: Sequence[tuple[str, str]]) -> dict[str, int]:
    """{name: value} of the options of ``counts`` (:func:`count_args`) the command line gives."""
    given = {flag.replace("-", "_"): getattr(args, flag.replace("-", "_")) for flag, _ in counts}
    return {k: v for k, v in given.items() if v is not None}


def stopped(work: Callable[[], int], line: Callable[[], str]) -> int:
    """The exit status of ``work``; where a stop signal ends it (SIGINT or SIGTERM, under the block of
    :func:`neurowalk.runners.stopping.stop_on_signals` that :func:`neurowalk.cli.main` holds around every command),
    ``line()`` on stderr, saying what is kept, and 130 (143 for SIGTERM)."""
    try:
        return work()
    except (KeyboardInterrupt, Exception) as e:
        if not interrupted(e):
            raise
        return stop_line(line())


def failed(line: str) -> int:
    """Print ``line`` on stderr, saying why a command failed (and what it keeps); its exit status, 1."""
    print(line, file=sys.stderr)
    return 1


def stop_line(line: str) -> int:
    """Print ``line`` on stderr, saying what a command a stop signal ended keeps; its exit status: 130 (SIGINT) or
    143 (SIGTERM)."""
    print(line, file=sys.stderr)
    return stop_status()


def control_hz_arg(p: argparse.ArgumentParser, default: float | None = 10.0, metavar: str = "HZ") -> None:
    """--control-hz: control steps per second (the networks step once per control step; physics follows)."""
    p.add_argument(
        "--control-hz",
        type=float if metavar == "HZ" else str,
        default=default,
        metavar=metavar,
        help="control rate, Hz (default 10, the authors' simulator; 27: the real AMOSII). The networks keep their "
        "step semantics (a CPG period is so many steps), so the robot walks faster at a higher rate",
    )


def engine_args(p: argparse.ArgumentParser) -> None:
    """--engine and --device (physics on CPU MuJoCo, as lock-step worlds on mujoco.batch threads, or on MuJoCo
    Warp)."""
    p.add_argument(
        "--engine",
        default="mujoco",
        help="physics engine: {engines} (default mujoco, on the CPU; mujoco.batch: the same runs, bit for bit, as "
        "lock-step worlds on CPU threads; warp: MuJoCo Warp, many worlds on a GPU; needs the warp extra)",
    )
    p.add_argument("--device", default=None, help="engine warp: cuda (default where a GPU is present) | cpu (slow)")


def check_engine(args: argparse.Namespace, named: Sequence[str] = ()) -> EngineOptions:
    """Check --engine/--device before any work (UsageError naming what to install or use); the engine options (the
    device resolved) that the command passes on to the runs. ``named``: engines the runs name themselves (a spec
    file's), checked as --engine is."""
    from neurowalk.sim.engine_interface import EngineOptions  # here: the simulation loads once the signals are handled
    from neurowalk.sim.engines import ENGINES

    names = list(dict.fromkeys([args.engine, *named]))
    for name in names:
        if name not in ENGINES:
            raise UsageError(f"unknown engine {name!r}; expected one of {', '.join(ENGINES)}")
    engines = [ENGINES[n] for n in names]
    chosen = next((e for e in engines if e.devices), engines[0])  # the engine that takes --device, if any
    if args.device is not None and not chosen.devices:
        with_device = " or ".join(f"--engine {name}" for name, e in ENGINES.items() if e.devices)
        raise UsageError(
            f"--device goes with {with_device} (engine {chosen.name!r} has no device), got {args.device!r}"
        )
    with usage_errors():
        return chosen.resolve(EngineOptions(device=args.device))


def variant_args(p: argparse.ArgumentParser, many: bool = False, only: str | None = None) -> None:
    """--variant and --params (``many``: --variant takes a comma list; ``only``: that one of the two)."""
    if only in (None, "variant"):
        p.add_argument(
            "--variant",
            default=None,
            metavar="NAME[,NAME...]" if many else "NAME",
            help="the network: {variants} (default paper: Eq. 1-6 as printed; original: the authors' code; "
            "see docs/paper-vs-code.md)",
        )
    if only in (None, "params"):
        p.add_argument(
            "--params",
            type=Path,
            default=None,
            metavar="FILE.json",
            help="SensoryParams fields on top of the variant, e.g. an `optimize` best.json; a file that names its "
            "variant is set over it (a --variant that says otherwise is refused), one that names none over --variant",
        )


def parse_variant(args: argparse.Namespace) -> tuple[str, dict | None]:
    """(variant, params overrides) of --variant/--params: a params file that names its base variant keeps it (a
    --variant that says otherwise is refused); one that names none is set over --variant (default paper)."""
    from neurowalk.neural.variants import get_variant, params_variant, read_params_file

    params = None
    variant = args.variant
    if variant is not None and not variant.strip():
        raise UsageError(f"--variant expects a name (e.g. paper, original), got {variant!r}")
    with usage_errors():
        if args.params is not None:
            data = read_params_file(args.params)
            params = data["params"]
            variant = params_variant(args.params, data, variant)
        variant = variant or "paper"
        get_variant(variant, params)
    return variant, params


def parse_arena_opts(items: list[str], flag: str = "--arena-opt") -> dict[str, str]:
    """{key: value} of the --arena-opt (or ``flag``) KEY=VALUE items."""
    opts = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise UsageError(f"{flag} expects KEY=VALUE, got {item!r}")
        opts[key] = value
    return opts


def parse_steer(text: str | None) -> tuple[float, float] | None:
    """(O1, O2) of --steer O1,O2, or None where it is not given."""
    if text is None:
        return None
    try:
        o1, o2 = (float(x) for x in text.split(","))
    except ValueError:
        raise UsageError(f"--steer expects two numbers O1,O2 in [-1, 1], got {text!r}") from None
    if not all(-1.0 <= v <= 1.0 for v in (o1, o2)):
        raise UsageError(f"--steer values must lie in [-1, 1], got {text!r}")
    return (o1, o2)


def episode_config(args: argparse.Namespace) -> EpisodeConfig:
    """The EpisodeConfig of the episode flags, its arena options checked; UsageError naming a bad value."""
    from neurowalk.arenas import make_arena
    from neurowalk.sim.episode import EpisodeConfig

    variant, params = parse_variant(args)
    with usage_errors():
        cfg = EpisodeConfig(
            arena=args.arena,
            arena_opts=parse_arena_opts(args.arena_opt),
            body_opts=parse_arena_opts(args.body_opt, "--body-opt"),  # before --steer, as the messages are ordered
            controller=args.controller,
            steer=parse_steer(args.steer),
            body=args.body,
            steps=args.steps,
            seed=args.seed,
            control_hz=args.control_hz,
            reflexes=args.reflexes or args.climb,
            backbone=args.backbone or args.climb,
            variant=variant,
            params=params,
            gait=args.gait,
            engine=getattr(args, "engine", "mujoco"),
        )
        make_arena(cfg.arena, **cfg.arena_opts)  # validate the arena's options before any work
    return cfg
