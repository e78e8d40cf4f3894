"""The planar two-finger hand with a passive palm (thesis §2.2.1, §2.3.2, Fig. 2.2, Fig. 2.13).

Public names: :class:`PlanarHand` (``.model``, ``.fingertip_positions(q)``,
``.jacobian(q, finger)``, ``.hand_jacobian``, ``.inverse_kinematics``), :class:`HandParams`,
:class:`FingerParams`, :func:`sample_reachable`, :func:`ball_workspace`,
:class:`WorkspaceMap`, :class:`ReachableSet`.
"""

from robots.planar_hand.hand import FingertipPose, PlanarHand
from robots.planar_hand.params import FINGERS, FingerParams, HandParams, default_finger
from robots.planar_hand.workspace import (
    ReachableSet,
    WorkspaceMap,
    ball_workspace,
    collision_free,
    sample_reachable,
)

__all__ = [
    "FINGERS",
    "FingerParams",
    "FingertipPose",
    "HandParams",
    "PlanarHand",
    "ReachableSet",
    "WorkspaceMap",
    "ball_workspace",
    "collision_free",
    "default_finger",
    "sample_reachable",
]
