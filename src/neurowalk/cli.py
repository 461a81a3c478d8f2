"""Command line: ``neurowalk figure NAME --out DIR`` and friends. Thin: parses, calls the library.

Bad input exits with status 2 and one line on stderr naming the offending value.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from neurowalk import __version__


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one clear line instead of usage + message
        raise UsageError(message)


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="neurowalk", description="Adaptive neural control of the hexapod AMOSII (Grinke et al. 2015).")
    p.add_argument("--version", action="version", version=f"neurowalk {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    f = sub.add_parser("figure", help="reproduce a paper figure: writes DIR/NAME.png and DIR/NAME.json")
    f.add_argument("name", help="figure name (see `neurowalk figure list`)")
    f.add_argument("--out", type=Path, default=None, help="output folder (default: out/NAME)")
    f.add_argument("--quick", action="store_true", help="shorter runs, coarser grids")
    f.add_argument("--seed", type=int, default=0, help="seed of every random draw (default 0)")
    f.add_argument("--replot", action="store_true", help="redraw from DIR/NAME.json and .npz without rerunning")
    return p


def _figure(args: argparse.Namespace) -> int:
    from neurowalk.experiments import FIGURES

    if args.name == "list":
        for name, exp in sorted(FIGURES.items()):
            print(f"{name:8s} {exp.title}")
        return 0
    if args.name not in FIGURES:
        raise UsageError(f"unknown figure {args.name!r}; available: {', '.join(sorted(FIGURES))}")
    if args.seed < 0:
        raise UsageError(f"--seed must be >= 0, got {args.seed}")
    from neurowalk.experiments import output

    exp = FIGURES[args.name]
    out = args.out or Path("out") / args.name
    t0 = time.perf_counter()
    if args.replot:
        if not (out / f"{args.name}.json").is_file():
            raise UsageError(f"--replot: no {args.name}.json in {str(out)!r}")
        result = output.load(args.name, out)
    else:
        result = exp.run(quick=args.quick, seed=args.seed)
    paths = output.save(result, exp.plot(result), out)
    print(f"{args.name}: wrote {', '.join(str(p) for p in paths.values())} in {time.perf_counter() - t0:.1f} s")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``neurowalk`` command; returns the exit status."""
    try:
        args = _parser().parse_args(argv)
        return {"figure": _figure}[args.command](args)
    except UsageError as e:
        print(f"neurowalk: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
