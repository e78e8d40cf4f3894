"""The planar world of the contact simulator (thesis ch. 2).

Public names: :class:`PlanarWorld`, :func:`compile_outline` (exact contact geometry of a
catalogue profile), :class:`Outline`.
"""

from planner.sim.planar.outline import Outline, compile_outline
from planner.sim.planar.world import PlanarWorld

__all__ = ["Outline", "PlanarWorld", "compile_outline"]
