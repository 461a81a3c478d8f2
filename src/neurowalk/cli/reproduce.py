"""The `reproduce` command: every result of the paper, judged, into DIR/NAME.json and DIR/report.md."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from neurowalk.cli.common import UsageError, out_folder, stop_line
from neurowalk.fileio import folder_lock

if TYPE_CHECKING:
    from neurowalk.experiments.reproduce.plan import Item
    from neurowalk.experiments.reproduce.runner import Run


def add_reproduce_parser(sub: argparse._SubParsersAction) -> None:
    """The `reproduce` subcommand."""
    r = sub.add_parser(
        "reproduce",
        help="run every experiment of the paper and judge each result: DIR/NAME.json, DIR/report.md (resumable)",
    )
    r.help_tail = _results_listing
    r.add_argument("--quick", action="store_true", help="each figure's --quick (fewer seeds, shorter runs)")
    r.add_argument("--only", default=None, metavar="NAME[,NAME...]", help="these results only (default: all)")
    r.add_argument("--out", type=Path, default=None, help="output folder (default out/reproduce, or -quick)")
    r.add_argument("--workers", type=int, default=None, help="processes of the figures of many runs (default 2)")
    r.add_argument("--list", action="store_true", help="list the results and their commands, run nothing")


def _results_listing() -> str:
    """The results the command measures, one per line (the end of its help)."""
    from neurowalk.experiments.reproduce.plan import PLAN

    width = max(len(i.name) for i in PLAN) + 2
    return "\nresults (--only):\n" + "".join(f"  {i.name:<{width}}{i.paper}\n" for i in PLAN)


def cmd_reproduce(args: argparse.Namespace) -> int:
    """`neurowalk reproduce`: run each figure command not yet finished in DIR, judge its results, write the report.

    Exit 0 where every run finished, 1 where one failed (the others still ran), 130 on a stop by SIGINT (143 by
    SIGTERM), with one line saying which results are on disk.
    """
    from neurowalk.experiments.reproduce import runner
    from neurowalk.experiments.reproduce.pinned import versions_line
    from neurowalk.experiments.reproduce.plan import settings_words
    from neurowalk.experiments.reproduce.report import write_report
    from neurowalk.experiments.reproduce.timing import expected_seconds

    items = _items(args.only)
    out = args.out or Path("out") / ("reproduce-quick" if args.quick else "reproduce")
    runs, run_of = runner.runs_of(items, args.quick, args.workers)
    if args.list:
        for item in items:
            run = run_of[item.name]
            print(f"{item.name:<15} figure {run.figure}: {settings_words(run.given)}")
        return 0
    out_folder(out)
    lock = folder_lock(out, "reproduce")
    if off := versions_line():
        print(off, file=sys.stderr)
    expected = {r.name: expected_seconds(r.figure, args.quick) for r in runs}
    failed: dict[str, str] = {}
    from tqdm import tqdm

    bar = tqdm(
        total=round(sum(expected.values())),
        desc="reproduce",
        file=sys.stderr,
        dynamic_ncols=True,
        bar_format="{desc} {percentage:3.0f}%|{bar}| {elapsed} so far, about {remaining} left",
    )  # weighted by each figure's time in the committed run
    base, t0 = 0.0, time.perf_counter()
    try:
        for k, run in enumerate(runs):
            bar.set_description(f"reproduce {k + 1}/{len(runs)} {run.name}")
            run_items = [i for i in items if run_of[i.name] is run]
            tick = partial(_show, bar, base, most=0.95 * expected[run.name])
            if _run_and_judge(run, run_items, out, args.quick, failed, tick):
                base += expected[run.name]
            else:  # finished before: the bar (and its time left) covers what is left to run
                bar.total = max(1, bar.total - round(expected[run.name]))
            _show(bar, base)
            write_report(out, args.quick, failed)
    except KeyboardInterrupt:
        bar.close()
        report = write_report(out, args.quick, failed)
        kept = [i.name for i in items if (out / f"{i.name}.json").is_file()]
        return stop_line(
            f"neurowalk: reproduce interrupted: {len(kept)} results are in {out} ({', '.join(kept) or 'none'}), "
            f"listed in {report}; the figures keep their finished runs: run the same command again to go on"
        )
    finally:
        lock.close()
    bar.close()
    report = write_report(out, args.quick, failed)
    print(runner.summary_line(out, args.quick, report, time.perf_counter() - t0))
    return 1 if failed else 0


def _items(only: str | None) -> list[Item]:
    """The plan's results named by ``--only`` (all where None), in the plan's order; UsageError naming an unknown."""
    from neurowalk.experiments.reproduce.plan import ITEMS, PLAN

    if only is None:
        return list(PLAN)
    names = [n.strip() for n in only.split(",")]
    unknown = [n for n in names if n not in ITEMS]
    if unknown or not all(names):
        raise UsageError(f"--only: unknown result {unknown[0] if unknown else ''!r}; results: {', '.join(ITEMS)}")
    return [i for i in PLAN if i.name in names]


def _run_and_judge(
    run: Run, items: list[Item], out: Path, quick: bool, failed: dict[str, str], tick: Callable[[float], None]
) -> bool:
    """Run ``run`` into ``out`` unless it finished there before (``tick``: its progress, in expected seconds), then
    judge each of its ``items``; ``failed`` gets an item's reason where its run failed or its judge could not read
    the run's numbers. True where the run ran now."""
    from neurowalk.experiments.output import failure_words
    from neurowalk.experiments.reproduce import runner

    record = runner.done(run, out)
    ran = record is None
    if ran:
        try:
            record = runner.execute(run, out, tick=tick)
        except runner.RunFailedError as e:
            for item in items:
                failed[item.name] = str(e)
            print(f"neurowalk: {e}", file=sys.stderr)
    if record is not None:
        for item in items:
            try:
                runner.write_item(item, run, record, out, quick)
            except (KeyError, TypeError, ValueError, IndexError) as e:  # numbers not of the judge's shape
                failed[item.name] = f"its judge could not read {run.figure}.json ({failure_words(e)})"
                (out / f"{item.name}.json").unlink(missing_ok=True)  # no verdict of an older run kept
                print(f"neurowalk: {item.name}: {failed[item.name]}", file=sys.stderr)
    return ran


def _show(bar: object, base: float, s: float = 0.0, most: float = 0.0) -> None:
    """Move the progress bar to ``base`` + ``s`` expected seconds, ``s`` at most ``most`` (95% of a run's expected
    time, where it is running)."""
    bar.n = round(base + min(s, most))  # type: ignore[attr-defined]
    bar.refresh()  # type: ignore[attr-defined]
