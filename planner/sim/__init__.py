"""The internal contact simulator (issue 15): rigid bodies, exact Coulomb friction, sensors.

Public names: :class:`PlanarWorld` (ch. 2: outlines, free bodies, the planar hand),
:class:`SpatialWorld` (ch. 4: the 3GM finger over surfaces; lazily imported),
:class:`Contact`, :class:`SimEvent`, :class:`Observation`, :class:`SensorSettings`,
:class:`SimLog`, :func:`run`, :func:`to_mjcf`, :func:`solve_lcp`.

The worlds import nothing above ``geometry``, ``contact``, ``optim`` and ``robots``.
"""

from __future__ import annotations

from typing import Any

from planner.sim.events import EVENT_KINDS, SimEvent
from planner.sim.log import SimLog
from planner.sim.loop import run
from planner.sim.observation import Observation, SensorSettings
from planner.sim.records import Contact

__all__ = [
    "EVENT_KINDS",
    "Contact",
    "Observation",
    "PlanarWorld",
    "SensorSettings",
    "SimEvent",
    "SimLog",
    "SpatialWorld",
    "run",
    "solve_lcp",
    "to_mjcf",
]

_LAZY = {
    "PlanarWorld": ("planner.sim.planar", "PlanarWorld"),
    "SpatialWorld": ("planner.sim.spatial", "SpatialWorld"),
    "to_mjcf": ("planner.sim.mjcf", "to_mjcf"),
    "solve_lcp": ("planner.sim.lcp", "solve_lcp"),
}


def __getattr__(name: str) -> Any:
    """Import the worlds on first use (B2's spatial world may be work in progress)."""
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        return getattr(importlib.import_module(module), attr)
    raise AttributeError(f"module 'planner.sim' has no attribute {name!r}")
