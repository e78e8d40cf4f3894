"""Contact kinematics and friction (thesis App. A.2, §2.2.2): the one home of friction.

* ``montana`` / ``integrate``: Montana's contact equations (A.12-A.13), two parametric
  surfaces advanced in contact;
* ``planar``: the pure-rolling reduction (eqs. 2.3-2.4, Table 2.1);
* ``friction``: contact types of Fig. 2.5, their wrench bases and the friction margins of
  eqs. 2.1-2.2;
* ``cones``: friction cones as edges (for wrench hulls) and facets (for QPs), eqs. 2.1, 2.2,
  2.9, and the normal/tangent frames they are built in.
"""

from planner.contact.cones import (
    cone_halfspaces,
    planar_cone_edges,
    pyramid_cone_edges,
    soft_finger_generators,
    tangent_basis,
    unit_directions,
)
from planner.contact.friction import (
    ContactType,
    point_contact_margin,
    soft_finger_margin,
    wrench_basis,
)
from planner.contact.integrate import ContactTrajectory, initial_pose, integrate_contact
from planner.contact.montana import VZ_TOLERANCE, montana_rates, r_psi
from planner.contact.planar import (
    TABLE_2_1,
    constraint_violations,
    planar_rolling_arc_length,
    planar_rolling_rates,
)

__all__ = [
    "TABLE_2_1",
    "VZ_TOLERANCE",
    "ContactTrajectory",
    "ContactType",
    "cone_halfspaces",
    "constraint_violations",
    "initial_pose",
    "integrate_contact",
    "montana_rates",
    "planar_cone_edges",
    "planar_rolling_arc_length",
    "planar_rolling_rates",
    "point_contact_margin",
    "pyramid_cone_edges",
    "r_psi",
    "soft_finger_generators",
    "soft_finger_margin",
    "tangent_basis",
    "unit_directions",
    "wrench_basis",
]
