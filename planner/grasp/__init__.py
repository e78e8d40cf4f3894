"""Grasp analysis and grasp-gait planning (thesis §2.2.1, §2.2.3, Figs. 2.4, 2.5, 2.11).

Contact types and friction cones live in :mod:`planner.contact`.

Public names:

* the grasp matrix (eq. 2.6) and hand Jacobian (eq. 2.5): :func:`grasp_matrix`,
  :func:`hand_jacobian`, :func:`joint_torques`;
* force closure: :func:`force_closure` (any k >= 2, planar or spatial),
  :func:`force_closure_two_planar` (exact, vectorized), :func:`force_closure_lp`;
* quality: :func:`epsilon_quality` (Ferrari–Canny, L1), :func:`epsilon_two_planar`;
* stability: :func:`two_contact_stability` (Yoshikawa–Nagai);
* maps and gaits: :func:`grasp_map`, :func:`workspace_map`, :func:`plan_gait`.
"""

from planner.grasp.closure import force_closure, force_closure_lp, force_closure_two_planar
from planner.grasp.gait import Gait, GaitPhase, plan_gait
from planner.grasp.grasp_matrix import grasp_matrix, hand_jacobian, joint_torques
from planner.grasp.maps import (
    GraspMap,
    contact_angles,
    grasp_map,
    hand_grasp_maps,
    shift_diagonal,
)
from planner.grasp.quality import epsilon_quality, epsilon_two_planar
from planner.grasp.stability import TwoContactStability, two_contact_stability
from planner.grasp.workspace import (
    HandReachability,
    ReachabilityModel,
    WorkspaceTables,
    workspace_map,
)
from planner.grasp.wrenches import primitive_wrenches

__all__ = [
    "Gait",
    "GaitPhase",
    "GraspMap",
    "HandReachability",
    "ReachabilityModel",
    "TwoContactStability",
    "WorkspaceTables",
    "contact_angles",
    "epsilon_quality",
    "epsilon_two_planar",
    "force_closure",
    "force_closure_lp",
    "force_closure_two_planar",
    "grasp_map",
    "grasp_matrix",
    "hand_grasp_maps",
    "hand_jacobian",
    "joint_torques",
    "plan_gait",
    "primitive_wrenches",
    "shift_diagonal",
    "two_contact_stability",
    "workspace_map",
]
