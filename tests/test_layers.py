"""Imports point one way (DESIGN §4) and no module imports another's private names: walked over the package."""

from __future__ import annotations

import ast
from pathlib import Path

import neurowalk

# Lower index, lower layer: a module may import from its own layer or a lower one.
LAYERS = (
    ("anatomy", "compiled", "fileio", "gym_registration", "observation"),
    ("neural",),
    ("controller", "gait"),
    ("body", "arenas", "metrics", "metrics_kernel"),
    ("sim", "render", "plotting"),
    ("runners",),
    ("experiments", "envs", "bench"),
    ("cli", "__main__"),
)
PKG = Path(neurowalk.__file__).parent


def _layer(parts: list[str]) -> int | None:
    return next((i for i, names in enumerate(LAYERS) if parts and parts[0] in names), None)


def _imports(path: Path) -> list[tuple[int, list[str], list[str]]]:
    """(line, target module parts below neurowalk, imported names) of every neurowalk import in ``path``."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("neurowalk"):
            out.append((node.lineno, node.module.split(".")[1:], [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            out += [(node.lineno, a.name.split(".")[1:], []) for a in node.names if a.name.startswith("neurowalk.")]
    return out


def violations(pkg: Path = PKG) -> list[str]:
    """Every upward import and every private name crossing a module boundary, as 'file:line: what'."""
    bad = []
    for f in sorted(pkg.rglob("*.py")):
        me = list(f.relative_to(pkg).with_suffix("").parts)
        for line, target, names in _imports(f):
            where = f"{f.relative_to(pkg)}:{line}"
            mine, theirs = _layer(me), _layer(target)
            if mine is not None and theirs is not None and theirs > mine:
                bad.append(f"{where}: {'.'.join(me)} (layer {mine}) imports {'.'.join(target)} (layer {theirs})")
            private = [n for n in names if n.startswith("_") and not n.startswith("__")]
            if private and target != me[: len(target)]:
                bad.append(f"{where}: imports private {', '.join(private)} from {'.'.join(target)}")
    return bad


def test_every_module_has_a_layer() -> None:
    top = {
        p.stem if p.is_file() else p.name for p in PKG.iterdir() if p.suffix == ".py" or (p / "__init__.py").exists()
    }
    assert {t for t in top if t != "__init__" and _layer([t]) is None} == set()


def test_imports_point_down_and_keep_private_names_private() -> None:
    assert violations() == []


def test_the_check_catches_an_upward_import_and_a_private_name(tmp_path: Path) -> None:
    (tmp_path / "neural").mkdir()
    (tmp_path / "neural" / "bad.py").write_text("from neurowalk.sim.episode import run_episode\n")
    (tmp_path / "metrics.py").write_text("from neurowalk.arenas.spec import _secret\n")
    found = violations(tmp_path)
    assert any("neural.bad (layer 1) imports sim.episode (layer 4)" in b for b in found)
    assert any("imports private _secret from arenas.spec" in b for b in found)
