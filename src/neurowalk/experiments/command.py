"""A study run as a command (``neurowalk figure``, ``neurowalk study``): one descent from the settings the command
line parsed to the runner, and the lines that say what came of it.

.. code-block:: text

    Settings ─► run_command ─► checked (names, the engine's device, the body the settings need) ─► folder made
                   │             ─► compute: runs through the one runner, measured ─► NAME.json, .npz, .png
                   │             (replot: NAME.json, .npz read back ─► NAME.png)
                   └─► one line of what it wrote (its claims where it is judged), or of what a stop keeps

Bad input is a :class:`CommandError`, raised before any work (the command line's one line and exit status 2); a
stop (SIGINT, SIGTERM) ends it with one line saying what is kept, and the stop's exit status (130, 143).
"""

from __future__ import annotations

import contextlib
import json
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from neurowalk.experiments import output
from neurowalk.experiments.study import Result, Settings, Study, compute, resolve
from neurowalk.experiments.study_runs import RunsStopped
from neurowalk.fileio import make_writable_folder
from neurowalk.runners.stopping import interrupted, stop_status
from neurowalk.runners.store import StoreError


class CommandError(ValueError):
    """Bad input of a study's command, found before any work: one line naming the value."""


def run_command(study: Study, settings: Settings, what: str, replot: bool = False) -> int:
    """Run ``study`` with ``settings`` as command ``what`` ("figure fig3") does: check and resolve the settings
    (:func:`checked`), make the folder ``settings.out``, compute the study and write NAME.json (NAME.npz) and NAME.png
    there (``replot``: redraw NAME.png from the numbers there), saying so in one line, then its claims where the
    command is the one the reproduction judges. Returns the exit status: 0, or after a stop the stop's (130 SIGINT,
    143 SIGTERM) with one line on stderr saying what is kept.

    Raises:
        CommandError: a bad setting, folder or saved file (one line), before any work; a folder made for the
            command is left as it was (removed while empty).
    """
    out = Path(settings.out or Path("out") / study.name)
    existed = out.exists()
    done: dict[str, Any] = {"stage": "start", "settings": settings}  # how far it got, for the line of a stop
    try:
        return _run(study, settings, out, what, replot, done)
    except CommandError:
        if not existed and out.is_dir() and not any(out.iterdir()):
            out.rmdir()  # made for this command, still empty: leave nothing behind
        raise
    except (KeyboardInterrupt, Exception) as e:  # a run stopped part-way in this process: RunInterruptedError
        if not (interrupted(e) or type(e).__name__ == "RunInterruptedError"):
            raise
        print(stop_words(study, what, replot, done, e), file=sys.stderr)
        return stop_status()


def _run(study: Study, settings: Settings, out: Path, what: str, replot: bool, done: dict[str, Any]) -> int:
    """:func:`run_command`'s work into folder ``out``; ``done`` says how far it got (its stage, its settings
    resolved, the files written)."""
    t0 = time.perf_counter()
    if settings.quick and not replot and _holds_full(study, out):
        name = study.name
        raise CommandError(f"--out {str(out)!r} holds {name}'s full result ({name}.json); a --quick run writes a "
                           f"folder of its own (by default out/{name}-quick), or name another --out")  # fmt: skip
    settings = done["settings"] = checked(study, settings, out)
    done["stage"], paths = "run", done.setdefault("paths", {})
    if not replot:
        try:
            result = compute(study, settings)
        except StoreError as e:
            raise CommandError(str(e)) from None
        except ValueError as e:  # a study checks its settings before it runs (e.g. a surrogate at 27 Hz)
            raise CommandError(f"{what}: {e}") from None
        output.write(study, result, out, paths)
    else:
        try:
            paths["png"] = output.redraw(study, out)
        except output.DataError as e:
            raise CommandError(str(e)) from None
    files = [paths[k] for k in ("png", "json", "npz") if k in paths]
    print(f"{study.name}: wrote {', '.join(str(p) for p in files)} in {time.perf_counter() - t0:.1f} s")
    if not replot and not settings.given():  # the command the reproduction judges: its claims, where it has any
        print("\n".join(claim_lines(study, result.summary, settings.quick)))
    return 0


def _holds_full(study: Study, out: Path) -> bool:
    """``out`` holds the study's full (not quick) result: NAME.json says ``"quick": false``."""
    try:
        return json.loads((out / f"{study.name}.json").read_text(encoding="utf-8")).get("quick") is False
    except (OSError, ValueError, AttributeError):
        return False


def checked(study: Study, s: Settings, out: Path) -> Settings:
    """``s`` checked and resolved before any work, its output folder ``out`` made (CommandError where it cannot be
    written): the body it names, or the body its other settings need (:func:`~neurowalk.experiments.study.resolve`);
    the engine's device resolved (a GPU, or Warp's CPU device, said in one line); the gait, network (variant and
    params) and box size it names exist. CommandError naming the value."""
    from neurowalk.arenas import make_arena
    from neurowalk.neural.cpg import GAITS
    from neurowalk.neural.variants import get_variant
    from neurowalk.sim.engine_interface import EngineOptions
    from neurowalk.sim.engines import ENGINES

    with _refused(f"--out {str(out)!r}: "):
        make_writable_folder(out)  # first: a folder that cannot be written is named before anything else
    with _refused():
        s = resolve(study, s.replace(out=out))  # also reads a params file
    if s.engine not in ENGINES:
        raise CommandError(f"unknown engine {s.engine!r}; expected one of {', '.join(ENGINES)}")
    engine = ENGINES[s.engine]
    if s.device is not None and not engine.devices:
        with_device = " or ".join(f"--engine {name}" for name, e in ENGINES.items() if e.devices)
        raise CommandError(f"--device goes with {with_device} (engine {s.engine!r} has no device), got {s.device!r}")
    with _refused():
        device = engine.resolve(EngineOptions(device=s.device)).device if engine.devices else s.device
    if s.gait is not None and s.gait not in GAITS:
        raise CommandError(f"unknown gait {s.gait!r}; expected one of {', '.join(GAITS)}")
    with _refused():
        if s.variant is not None or s.params is not None:
            get_variant(s.variant or "paper", s.params)
    if s.size is not None:
        with _refused(f"--arena-opt size={s.size:g}: "):
            make_arena("random", size=s.size, n_boxes=0)  # the arena's own range check
    return s if device == s.device else s.replace(device=device)


@contextlib.contextmanager
def _refused(prefix: str = "") -> Iterator[None]:
    """A ValueError in the block as a CommandError: ``prefix`` and its message."""
    try:
        yield
    except ValueError as e:
        raise CommandError(f"{prefix}{e}") from None


def stop_words(study: Study, what: str, replot: bool, done: dict[str, Any], stop: BaseException) -> str:
    """The line of a command that ``stop`` ended where ``done`` says (its stage: "start" while its settings were
    checked, "run"; the files it wrote): what it wrote, or the finished runs its result stores keep, as the runner
    said (:class:`~neurowalk.experiments.study_runs.RunsStopped`; another stop came before its runs began)."""
    name = study.name
    paths = done.get("paths", {})
    files = ", ".join(str(paths[k]) for k in ("png", "json", "npz") if k in paths)
    if done["stage"] == "start":
        return f"neurowalk: {what} interrupted before it began; nothing was run"
    if replot:
        return f"neurowalk: {name} interrupted while drawing; nothing written"
    if "png" in paths:
        return f"neurowalk: {name} interrupted as it ended; it wrote {files}"
    if paths:
        return f"neurowalk: {name} interrupted while drawing: its numbers are in {files}; `--replot` draws it"
    if not isinstance(stop, RunsStopped):
        return f"neurowalk: {name} interrupted before its runs began; no run began now"
    return interrupted_line(name, stop.kept)


def claim_lines(study: Study, summary: dict[str, Any], quick: bool) -> list[str]:
    """The results ``study`` judges (its claims, those of ``neurowalk reproduce``) from ``summary``: one line each
    (what, the paper's value, neurowalk's, the verdict) and where the rules are (none: no judged result)."""
    from neurowalk.experiments.reproduce.report import cell

    claims = study.claims(summary, quick) if study.claims is not None else []
    if not claims:
        return []
    name = study.name
    lines = [f"{name} against the paper{' (--quick: fewer, shorter runs)' if quick else ''}:"]
    rows = summary.get("counts")
    if isinstance(rows, dict) and all(
        isinstance(r, dict) and {"success", "environments"} <= set(r) for r in rows.values()
    ):
        lines.append("  successes: " + ", ".join(f"{k} {r['success']}/{r['environments']}" for k, r in rows.items()))
    for c in claims:
        paper, measured = (cell(v, c.unit, markdown=False) for v in (c.paper, c.measured))
        lines.append(f"  {c.what}: paper {paper}, neurowalk {measured} -> {c.verdict}")
    lines.append(f"  (the rules and the full runs' verdicts: docs/results/details.md#{name})")
    return lines


def interrupted_line(name: str, kept: dict[Path, int] | None) -> str:
    """The line of a study interrupted while it ran: the finished runs ``kept`` in its result stores, by file
    (:func:`~neurowalk.experiments.study.kept_runs`; None: the study runs no episode)."""
    if kept is None:
        return f"neurowalk: {name} interrupted; it runs no episode (the network alone), so none is kept: run it again"
    if not kept:
        return f"neurowalk: {name} interrupted before any of its runs finished; nothing is kept"
    return f"neurowalk: {name} interrupted: {_kept_in(kept)}; run the same command again to go on from them"


def kept_words(kept: dict[Path, int] | None) -> str:
    """What a failed study keeps, in words: ``61 finished runs are kept in out/gap (61 in results.sqlite): fix it and
    run the same command to go on from them``, or that none is (None: it runs no episode)."""
    if kept is None:
        return "it runs no episode: nothing is kept"
    if not kept:
        return "none of its runs had finished: nothing is kept"
    return f"{_kept_in(kept)}: fix it and run the same command to go on from them"


def _kept_in(kept: dict[Path, int]) -> str:
    """The finished runs of ``kept`` and their stores in words: ``65 finished runs are kept in out/fig3 (61 in
    results.sqlite, 4 in track.sqlite)``."""
    folders = sorted({str(p.parent) for p in kept})
    where = f"{', '.join(folders)} ({', '.join(f'{n} in {p.name}' for p, n in kept.items())})"
    return f"{sum(kept.values())} finished runs are kept in {where}"


__all__ = ["CommandError", "Result", "checked", "claim_lines", "run_command"]
