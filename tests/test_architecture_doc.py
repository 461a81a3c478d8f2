"""docs/architecture.md matches the code: every module it names exists, every name it gives is there, and its
engine table lists the engines of the one table (sim/engines.py)."""

import importlib
import re
from pathlib import Path

import neurowalk
from neurowalk.body.registry import BODIES, BodyInfo
from neurowalk.sim import engine_interface as engine_module
from neurowalk.sim.engines import ENGINES, PLANAR

DOC = Path(__file__).resolve().parents[1] / "docs" / "architecture.md"
SRC = Path(neurowalk.__file__).resolve().parent


def test_every_module_the_page_names_exists():
    text = DOC.read_text()
    paths = set(re.findall(r"\b((?:[a-z_]+/)+[a-z_]+\.py)\b", text))
    assert len(paths) > 10
    for p in paths:
        assert (SRC / p).is_file() or (DOC.parents[1] / p).is_file(), p


def test_every_dotted_name_the_page_gives_is_there():
    text = DOC.read_text()
    names = set(re.findall(r"`([a-z_]+(?:/[a-z_]+)?)\.([A-Za-z_]+)`", text))
    assert len(names) > 5
    for module, attr in names:
        if attr in ("py", "json", "md", "png", "npz") or module == "mujoco":  # a file; MuJoCo's own mujoco.batch
            continue
        mod = importlib.import_module("neurowalk." + module.replace("/", "."))
        assert hasattr(mod, attr), f"{module}.{attr}"


def test_the_interfaces_have_what_the_page_says():
    text = DOC.read_text()
    for method in re.findall(r"    def ([a-z_]+)\(self", text):
        assert hasattr(engine_module.Engine, method), method
    outline = text.split("class Engine(ABC):", 1)[1].split("```", 1)[0]
    attrs = re.findall(r"^    ([a-z_]+): ", outline, re.M)  # the interface's attributes, as the page outlines it
    assert set(attrs) == set(engine_module.Engine.__annotations__)
    for engine in (*ENGINES.values(), PLANAR):  # and every engine has them
        assert all(hasattr(engine, attr) for attr in attrs), engine
    for name in ENGINES:
        assert f"`{name}`" in text
    for field in ("engines", "climbs_on", "surrogate", "action", "physics", "climbs"):
        assert field in BodyInfo.__dataclass_fields__ and field in text
    for body in BODIES:
        assert f"`{body}`" in text, body
