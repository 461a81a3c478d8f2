"""Cheap stand-ins for ``run_spec`` in engine tests: module-level, so worker processes (local pool, Ray) import them.

Workers import this module by name (``sweep_fns``): pytest puts this folder on ``sys.path``; forked workers inherit
it and the Ray fixture passes it on in ``PYTHONPATH``.
"""

from __future__ import annotations

import os
from typing import Any


def cheap(spec: dict[str, Any]) -> dict[str, Any]:
    """A result that depends only on the spec (like a seeded run), with a nested value."""
    x = (spec["seed"] * 7919 + spec["steps"]) % 1000 / 1000
    return {"seed": spec["seed"], "x": x, "pair": [x, -x], "label": f"s{spec['seed']}", "pid": None}


def fail_on_seed_3(spec: dict[str, Any]) -> dict[str, Any]:
    """Like :func:`cheap`, but seed 3 raises (with a two-line message)."""
    if spec["seed"] == 3:
        raise ValueError("seed 3 is cursed\nsecond line that must not show")
    return cheap(spec)


def die_on_seed_2(spec: dict[str, Any]) -> dict[str, Any]:
    """Like :func:`cheap`, but the process running seed 2 dies at once (as a segfault would)."""
    if spec["seed"] == 2:
        os._exit(1)
    return cheap(spec)


def not_a_dict(spec: dict[str, Any]) -> Any:
    """A bad fn: returns a list."""
    return [spec["seed"]]


def slow(spec: dict[str, Any]) -> dict[str, Any]:
    """Like :func:`cheap`, after sleeping ``spec["sleep"]`` seconds (a long run)."""
    import time

    time.sleep(spec["sleep"])
    return cheap(spec)


def die_counting(spec: dict[str, Any]) -> dict[str, Any]:
    """Like :func:`cheap`, but notes each start in ``spec["log"]``; seed 2 kills its process, on every start or,
    with ``spec["once"]``, on its first only (a flaky crash)."""
    with open(spec["log"], "a") as f:
        f.write(f"{spec['seed']}\n")
    if spec["seed"] == 2:
        with open(spec["log"]) as f:
            starts = f.read().split().count("2")
        if not spec.get("once") or starts == 1:
            os.kill(os.getpid(), 9)
    return cheap(spec)
