"""Feature-guided exploration of a fixed surface with the 3GM and the OWTS (thesis ch. 4).

:func:`explore_surface` searches a plate, identifies each feature's type (§4.4.1), traces its
boundary (§4.4.2) and builds the feature and global skeletons (§4.4.3, §4.5), closed-loop in
:class:`planner.sim.SpatialWorld` under the hybrid force/velocity law of §4.3.
"""

from importlib import import_module

__all__ = ["ExplorationResult", "ExploredFeature", "explore_surface"]

_HOMES = {
    "explore_surface": "planner.exploration.surface.explorer",
    "ExplorationResult": "planner.exploration.surface.result",
    "ExploredFeature": "planner.exploration.surface.result",
}


def __getattr__(name: str):
    if name in _HOMES:
        return getattr(import_module(_HOMES[name]), name)
    raise AttributeError(f"module 'planner.exploration.surface' has no attribute {name!r}")
