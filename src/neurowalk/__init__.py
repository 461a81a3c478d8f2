"""neurowalk: adaptive neural control of the walking robot AMOSII (Grinke et al. 2015) on MuJoCo."""

import sys

from neurowalk.anatomy import ACTUATORS, LEGS
from neurowalk.controller import Controller, FixedController, NeuralController
from neurowalk.neural.sensory import SensoryParams, simulate
from neurowalk.observation import Observation

__version__ = "0.1.0"

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
