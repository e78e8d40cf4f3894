"""Contact kinematics and friction (thesis App. A.2, §2.2.2).

``montana_rates`` implements Montana's contact equations (A.12-A.13); ``integrate_contact``
advances two parametric surfaces in contact; ``planar`` holds the pure-rolling reduction
(eqs. 2.3-2.4, Table 2.1); ``friction`` the constraints of eqs. 2.1-2.2.
"""

from planner.contact.friction import point_contact_margin, soft_finger_margin
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
    "constraint_violations",
    "initial_pose",
    "integrate_contact",
    "montana_rates",
    "planar_rolling_arc_length",
    "planar_rolling_rates",
    "point_contact_margin",
    "r_psi",
    "soft_finger_margin",
]
