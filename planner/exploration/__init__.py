"""Exploration executed on the simulator: the ch. 2 grasp gait and the ch. 4 explorer.

- :func:`explore_object` (``planner.exploration.planar``): two fingers and a palm rotate an
  unknown planar object a full turn with the 3-phase gait while sensing its outline (ch. 2).
- :func:`explore_surface` (``planner.exploration.surface``): the 3GM finger searches a fixed
  surface, identifies each feature's type, traces it and builds the skeletons (ch. 4).

Both are imported on first use, so ``import planner.exploration`` stays light.
"""

from __future__ import annotations

from importlib import import_module

__all__ = ["explore_object", "explore_surface"]

_HOMES = {
    "explore_object": "planner.exploration.planar",
    "explore_surface": "planner.exploration.surface",
}


def __getattr__(name: str):
    if name in _HOMES:
        return getattr(import_module(_HOMES[name]), name)
    raise AttributeError(f"module 'planner.exploration' has no attribute {name!r}")
