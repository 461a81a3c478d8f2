"""neurowalk: adaptive neural control of the walking robot AMOSII (Grinke et al. 2015) on MuJoCo.

The names below load on first use, so that the ``neurowalk`` command starts at once (and a Ctrl-C while it
starts is answered in one line, by the command, not by a traceback from deep inside an import).
"""

import importlib
import sys
from typing import Any

__version__ = "0.1.0"

_LAZY = {
    "ACTUATORS": "neurowalk.anatomy",
    "LEGS": "neurowalk.anatomy",
    "Controller": "neurowalk.controller",
    "FixedController": "neurowalk.controller",
    "NeuralController": "neurowalk.controller",
    "SensoryParams": "neurowalk.neural.sensory",
    "simulate": "neurowalk.neural.sensory",
    "Observation": "neurowalk.observation",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'neurowalk' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})


if "gymnasium" in sys.modules:  # `import gymnasium, neurowalk`: the environment ids are registered
    from neurowalk.envs import register_envs

    register_envs()

__all__ = [
    "ACTUATORS",
    "LEGS",
    "Controller",
    "FixedController",
    "NeuralController",
    "Observation",
    "SensoryParams",
    "__version__",
    "simulate",
]
