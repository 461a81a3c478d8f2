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

from neurowalk.gym_registration import ENVIRONMENTS, register_envs

IDS: tuple[str, ...] = tuple(ENVIRONMENTS)

register_envs()
