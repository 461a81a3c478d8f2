"""Imports point one way (DESIGN §4) and no module imports another's private names: walked over the package."""

from __future__ import annotations

import ast
from pathlib import Path

import neurowalk

# Lower index, lower layer: a module may import from its own layer or a lower one.
LAYERS = (
    ("anatomy", "compiled", "cpu", "fileio", "fingerprint", "observation", "profiling", "progress"),
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


def _module_of(pkg: Path, target: list[str]) -> str | None:
    """The module (dotted, below neurowalk) that an import target names: the longest prefix that is a file."""
    for n in range(len(target), 0, -1):
        p = pkg.joinpath(*target[:n])
        if p.with_suffix(".py").is_file():
            return ".".join(target[:n])
    return None


def circles(pkg: Path = PKG) -> list[list[str]]:
    """Groups of modules that import each other, directly or through others (imports inside functions count: they
    hide a circle, they do not remove it); package ``__init__`` files, which only re-export, are left out."""
    graph: dict[str, set[str]] = {}
    for f in sorted(pkg.rglob("*.py")):
        if f.name == "__init__.py":
            continue
        me = ".".join(f.relative_to(pkg).with_suffix("").parts)
        for _, target, names in _imports(f):
            for t in [[*target, n] for n in names] or [target]:
                mod = _module_of(pkg, t)
                if mod and mod != me:
                    graph.setdefault(me, set()).add(mod)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    out: list[list[str]] = []

    def visit(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_modules_import_each_other() -> None:
    assert circles() == []


def test_the_circle_check_finds_a_circle_through_a_function(tmp_path: Path) -> None:
    (tmp_path / "sim").mkdir()
    (tmp_path / "sim" / "a.py").write_text("from neurowalk.sim.b import x\n")
    (tmp_path / "sim" / "b.py").write_text("def f():\n    from neurowalk.sim.c import y\n")
    (tmp_path / "sim" / "c.py").write_text("from neurowalk.sim import a\n")
    assert circles(tmp_path) == [["sim.a", "sim.b", "sim.c"]]
