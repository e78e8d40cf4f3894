"""The planar two-finger hand with a passive palm (thesis §2.2.1, §2.3.2, Fig. 2.2, Fig. 2.13).

Public names: :class:`PlanarHand` (``.model``, ``.fingertip_positions(q)``,
``.jacobian(q, finger)``, ``.hand_jacobian``, ``.inverse_kinematics``), :class:`HandParams`,
:class:`FingerParams`, :func:`gait_hand_params` (the executed gait's wider joint ranges),
:func:`ranged_hand_params`, :func:`sample_reachable`, :func:`ball_workspace`,
:class:`WorkspaceMap`, :class:`ReachableSet`.
"""

from robots.planar_hand.hand import FingertipPose, PlanarHand
from robots.planar_hand.params import (
    FINGERS,
    GAIT_LOWER_DEG,
    GAIT_UPPER_DEG,
    FingerParams,
    HandParams,
    default_finger,
    gait_hand_params,
    ranged_hand_params,
)
from robots.planar_hand.workspace import (
    ReachableSet,
    WorkspaceMap,
    ball_workspace,
    collision_free,
    sample_reachable,
)

__all__ = [
    "FINGERS",
    "GAIT_LOWER_DEG",
    "GAIT_UPPER_DEG",
    "FingerParams",
    "FingertipPose",
    "HandParams",
    "PlanarHand",
    "ReachableSet",
    "WorkspaceMap",
    "ball_workspace",
    "collision_free",
    "default_finger",
    "gait_hand_params",
    "ranged_hand_params",
    "sample_reachable",
]
