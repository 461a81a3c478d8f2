"""neurowalk's Gymnasium environment ids, registered with Gymnasium as soon as both are imported (in any order).

Gymnasium 1.x loads no plugins by entry point, so ``import neurowalk`` does it: where Gymnasium is imported already,
it registers the ids at once; where it is not, it registers them right after Gymnasium's own import
(:class:`RegisterAfterImport`, a finder on ``sys.meta_path`` that removes itself), so that ``import neurowalk`` does
not pay for importing Gymnasium (about 0.2 s) when nothing needs it. Then ``gymnasium.make("neurowalk/Explore-v0")``
works without importing :mod:`neurowalk.envs` first.
"""

from __future__ import annotations

import sys

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (a start-up that a Ctrl-C may meet)
if TYPE_CHECKING:
    from collections.abc import Sequence
    from types import ModuleType
    from typing import Any

__all__ = ["ENVIRONMENTS", "RegisterAfterImport", "register_envs", "register_when_gymnasium_loads"]

#: id -> (entry point, vector entry point); the classes live in :mod:`neurowalk.envs`.
ENVIRONMENTS: dict[str, tuple[str, str]] = {
    "neurowalk/Explore-v0": ("neurowalk.envs.explore:ExploreEnv", "neurowalk.envs.vector:ExploreVectorEnv"),
    "neurowalk/ExplorePhysics-v0": (
        "neurowalk.envs.physics:ExplorePhysicsEnv",
        "neurowalk.envs.physics_vector:ExplorePhysicsVectorEnv",
    ),
}


def register_envs() -> None:
    """Register neurowalk's environment ids with Gymnasium (each once)."""
    from gymnasium.envs.registration import register, registry

    for env_id, (entry, vector_entry) in ENVIRONMENTS.items():
        if env_id not in registry:
            register(id=env_id, entry_point=entry, vector_entry_point=vector_entry)


class RegisterAfterImport:
    """A meta-path finder (the protocol of ``importlib.abc.MetaPathFinder``, not imported: ``import neurowalk`` stays
    as light as a Ctrl-C at start-up needs): finds ``gymnasium`` as the other finders do, and has its loader register
    neurowalk's ids after it ran."""

    def find_spec(self, fullname: str, path: Sequence[str] | None = None, target: ModuleType | None = None) -> Any:
        if fullname != "gymnasium":
            return None
        sys.meta_path.remove(self)  # once; and find_spec below must not find this finder again
        import importlib.util  # here, not at the top: `import neurowalk` stays light (the command's start-up)

        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None:
            return spec
        run = spec.loader.exec_module

        def exec_and_register(module: ModuleType) -> None:
            run(module)
            register_envs()

        spec.loader.exec_module = exec_and_register  # type: ignore[method-assign]
        return spec


def register_when_gymnasium_loads() -> None:
    """Register the ids now if Gymnasium is imported, else right after its import (if it is ever imported)."""
    if "gymnasium" in sys.modules:
        register_envs()
    elif not any(isinstance(f, RegisterAfterImport) for f in sys.meta_path):
        sys.meta_path.insert(0, RegisterAfterImport())
