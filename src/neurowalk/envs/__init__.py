"""Gymnasium environments over neurowalk's bodies (needs the ``gym`` extra: ``pip install -e '.[gym]'``).

``neurowalk/Explore-v0``: the planar surrogate in a random Table 2 environment, steered by an agent
(:class:`~neurowalk.envs.explore.ExploreEnv`; vectorised: :class:`~neurowalk.envs.vector.ExploreVectorEnv`).
``neurowalk/ExplorePhysics-v0``: the same task on the MuJoCo AMOSII, steered or driven joint by joint
(:class:`~neurowalk.envs.physics.ExplorePhysicsEnv`; vectorised in one MuJoCo batch:
:class:`~neurowalk.envs.physics_vector.ExplorePhysicsVectorEnv`). The ids are registered by ``import neurowalk``
(:mod:`neurowalk.gym_registration`), in whichever order it and Gymnasium are imported:
``import neurowalk, gymnasium; gymnasium.make("neurowalk/Explore-v0")``.
"""

from __future__ import annotations

import os

from neurowalk.gym_registration import ENVIRONMENTS, register_envs

IDS: tuple[str, ...] = tuple(ENVIRONMENTS)

register_envs()

if not os.environ.get("DISPLAY"):  # no screen: render_mode="rgb_array" of the physics environments renders offscreen
    from neurowalk.render import use_headless_gl

    use_headless_gl()  # EGL, unless MUJOCO_GL is set or MuJoCo was imported before (then it is too late to choose)
