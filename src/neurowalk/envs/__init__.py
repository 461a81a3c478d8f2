"""Gymnasium environments over neurowalk's bodies (needs the ``gym`` extra: ``pip install -e '.[gym]'``).

``neurowalk/Explore-v0``: the planar surrogate in a random Table 2 environment, steered by an agent
(:class:`~neurowalk.envs.explore.ExploreEnv`; vectorised: :class:`~neurowalk.envs.vector.ExploreVectorEnv`).
``neurowalk/ExplorePhysics-v0``: the same task on the MuJoCo AMOSII, steered or driven joint by joint
(:class:`~neurowalk.envs.physics.ExplorePhysicsEnv`; vectorised in one MuJoCo batch:
:class:`~neurowalk.envs.physics_vector.ExplorePhysicsVectorEnv`).

Importing this package registers the ids (Gymnasium 1.x loads no plugins by entry point), in Gymnasium's own two
ways: ``import neurowalk.envs`` (``gymnasium.register_envs(neurowalk.envs)`` says so to a linter), or the id's
module prefix, which has ``gymnasium.make`` import it: ``gymnasium.make("neurowalk.envs:neurowalk/Explore-v0")``.
``import neurowalk`` alone imports neither Gymnasium nor this package, and installs no import hook.
"""

from __future__ import annotations

from gymnasium.envs.registration import register, registry

#: id -> (entry point, vector entry point).
ENVIRONMENTS: dict[str, tuple[str, str]] = {
    "neurowalk/Explore-v0": ("neurowalk.envs.explore:ExploreEnv", "neurowalk.envs.vector:ExploreVectorEnv"),
    "neurowalk/ExplorePhysics-v0": (
        "neurowalk.envs.physics:ExplorePhysicsEnv",
        "neurowalk.envs.physics_vector:ExplorePhysicsVectorEnv",
    ),
}
IDS: tuple[str, ...] = tuple(ENVIRONMENTS)


def register_envs() -> None:
    """Register neurowalk's environment ids with Gymnasium (each once; importing this package does it)."""
    for env_id, (entry, vector_entry) in ENVIRONMENTS.items():
        if env_id not in registry:
            register(id=env_id, entry_point=entry, vector_entry_point=vector_entry)


register_envs()
