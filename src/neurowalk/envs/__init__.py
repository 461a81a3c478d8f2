"""Gymnasium environments over neurowalk's bodies (needs the ``gym`` extra: ``pip install neurowalk[gym]``).

``neurowalk/Explore-v0``: the planar surrogate in a random Table 2 environment, steered by an agent
(:class:`~neurowalk.envs.explore.ExploreEnv`; vectorised: :class:`~neurowalk.envs.vector.ExploreVectorEnv`).
``neurowalk/ExplorePhysics-v0``: the same task on the MuJoCo AMOSII, steered or driven joint by joint
(:class:`~neurowalk.envs.physics.ExplorePhysicsEnv`; vectorised in one MuJoCo batch:
:class:`~neurowalk.envs.physics_vector.ExplorePhysicsVectorEnv`). The ids are registered when this package is
imported, and by ``import neurowalk`` where Gymnasium is imported already: ``import gymnasium, neurowalk;
gymnasium.make("neurowalk/Explore-v0")``; in any order, ``gymnasium.make("neurowalk.envs:neurowalk/Explore-v0")``.
(Gymnasium 1.x loads no plugins by entry point.)
"""

from __future__ import annotations

import os

IDS: tuple[str, ...] = ("neurowalk/Explore-v0", "neurowalk/ExplorePhysics-v0")


def register_envs() -> None:
    """Register neurowalk's environment ids with Gymnasium (the ``gymnasium.envs`` entry point calls this)."""
    from gymnasium.envs.registration import register, registry

    if "neurowalk/Explore-v0" not in registry:
        register(
            id="neurowalk/Explore-v0",
            entry_point="neurowalk.envs.explore:ExploreEnv",
            vector_entry_point="neurowalk.envs.vector:ExploreVectorEnv",
        )
    if "neurowalk/ExplorePhysics-v0" not in registry:
        register(
            id="neurowalk/ExplorePhysics-v0",
            entry_point="neurowalk.envs.physics:ExplorePhysicsEnv",
            vector_entry_point="neurowalk.envs.physics_vector:ExplorePhysicsVectorEnv",
        )


register_envs()

if not os.environ.get("DISPLAY"):  # no screen: render_mode="rgb_array" of the physics environments renders offscreen
    from neurowalk.render import use_headless_gl

    use_headless_gl()  # EGL, unless MUJOCO_GL is set or MuJoCo was imported before (then it is too late to choose)
