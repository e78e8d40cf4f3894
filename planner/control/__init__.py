"""Controllers (the next issues fill this package) and the grasp-force distribution QP.

Every QP goes through :mod:`planner.optim`; here :class:`GraspForceQP` builds the grasp-force
distribution problem of one grasp once and re-solves it in place (eqs. 2.1, 2.6, 2.9).
"""

from planner.control.force_distribution import (
    OBJECTIVES,
    ForceDistribution,
    GraspForceQP,
    distribute_forces,
)

__all__ = ["OBJECTIVES", "ForceDistribution", "GraspForceQP", "distribute_forces"]
