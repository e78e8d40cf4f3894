"""The spatial world of the contact simulator (ch. 4): the 3GM fingertip and free balls on
exact surfaces, with an exact circular Coulomb cone at every step.

Public names: :class:`SpatialWorld`, :class:`Plane`, :class:`Plate`, :class:`PlateFeature`,
:data:`FEATURE_KINDS`, :class:`OWTSReading`, :func:`solve_contact` (the exact 3x3 contact
problem), :func:`tcs_rotation` (TCS -> WCS of the simulated OWTS).
"""

from planner.sim.spatial.finger import tcs_rotation
from planner.sim.spatial.friction_cone import ContactSolution, solve_contact
from planner.sim.spatial.plate import FEATURE_KINDS, Plane, Plate, PlateFeature
from planner.sim.spatial.sensing import OWTSReading
from planner.sim.spatial.world import SpatialWorld

__all__ = [
    "FEATURE_KINDS",
    "ContactSolution",
    "OWTSReading",
    "Plane",
    "Plate",
    "PlateFeature",
    "SpatialWorld",
    "solve_contact",
    "tcs_rotation",
]
