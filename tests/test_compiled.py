"""numba's cache never runs stale code: editing a callee in another file gives the new behaviour at once."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import neurowalk
from neurowalk import compiled

PROBE = """
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np
import neurowalk
assert neurowalk.__file__.startswith(sys.argv[1]), neurowalk.__file__
from neurowalk.neural.motor import LocomotionNetwork
net = LocomotionNetwork()
for _ in range(30):
    net.step(-1.0, -1.0)
print(repr(float(net.cpg[0])), neurowalk.compiled.cache_dir())
"""


def _probe(pkg: Path, cache: Path) -> tuple[str, str]:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    out = subprocess.run([sys.executable, "-c", PROBE, str(pkg)], env=env, capture_output=True, text=True, check=True)
    value, where = out.stdout.split()
    return value, where


def test_an_edited_callee_in_another_file_is_recompiled(tmp_path: Path) -> None:
    pkg = tmp_path / "pkg"
    shutil.copytree(Path(neurowalk.__file__).parent, pkg / "neurowalk", ignore=shutil.ignore_patterns("__pycache__"))
    cache = tmp_path / "cache"
    before, dir1 = _probe(pkg, cache)
    again, dir2 = _probe(pkg, cache)  # from the cache: same code, same place
    assert (again, dir2) == (before, dir1) and any(Path(dir1).rglob("*.nbi"))
    cpg = pkg / "neurowalk" / "neural" / "cpg.py"  # motor.presignal_step calls cpg.cpg_step
    text = cpg.read_text()
    edited = text.replace("    o[1] = math.tanh(-w_cross * o0 + w_self * o1)\n",
                          "    o[1] = math.tanh(-w_cross * o0 + w_self * o1)\n    o[0] = 0.25\n")  # fmt: skip
    assert edited != text
    cpg.write_text(edited)
    after, dir3 = _probe(pkg, cache)
    assert float(after) == 0.25 and float(before) != 0.25  # the callee's new code runs in the caller
    assert dir3 != dir1


def test_the_cache_key_names_the_version_and_the_source() -> None:
    key = compiled.source_key()
    version, digest = key.rsplit("-", 1)
    assert version and len(digest) == 16
    assert compiled.cache_dir().name == key
