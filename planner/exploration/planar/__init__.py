"""The ch. 2 grasp gait executed in the planar world (thesis §2.2-2.3, Fig. 2.3).

Public names: :func:`explore_object`, its :class:`ExplorationResult` (with
:class:`PhaseRecord` and :class:`DetectedFeature`), the :class:`GaitSettings`, and the
object helper :func:`circle_with_ridge` (the ball of §2.3.2).
"""

from planner.exploration.planar.machine import explore_object
from planner.exploration.planar.objects import circle_with_ridge
from planner.exploration.planar.result import DetectedFeature, ExplorationResult, PhaseRecord
from planner.exploration.planar.settings import GaitSettings

__all__ = [
    "DetectedFeature",
    "ExplorationResult",
    "GaitSettings",
    "PhaseRecord",
    "circle_with_ridge",
    "explore_object",
]
